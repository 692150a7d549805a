// SPDX-License-Identifier: Apache-2.0
// Control protocol: the documented request/reply/event shapes, and an error naming the problem
// for every kind of malformed or out-of-range request.

#include <gtest/gtest.h>

#include <string>

#include "navmap/ipc/control/control_protocol.h"

using namespace navmap::ipc;

TEST(ControlProtocol, ParsesTheDocumentedSetRoute) {
    const auto r = parseControlLine(
        R"({"cmd":"set_route","id":"r1","points":[[42.5075,1.5218],[42.51,1.53]],"maneuvers":[{"index":1,"type":"turn_left","text":"CG-2"}]})");
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_EQ(r.command->cmd, "set_route");
    EXPECT_EQ(r.command->request_id, "r1");
    const auto& route = std::get<SetRouteCommand>(r.command->body);
    EXPECT_EQ(route.route_id, "r1");
    ASSERT_EQ(route.points.size(), 2U);
    EXPECT_DOUBLE_EQ(route.points[0].lat_deg, 42.5075);
    EXPECT_DOUBLE_EQ(route.points[1].lon_deg, 1.53);
    ASSERT_EQ(route.maneuvers.size(), 1U);
    EXPECT_EQ(route.maneuvers[0].index, 1U);
    EXPECT_EQ(route.maneuvers[0].type, ManeuverType::TurnLeft);
    EXPECT_EQ(route.maneuvers[0].text, "CG-2");
}

TEST(ControlProtocol, RoundaboutManeuversCarryAnOptionalExitNumber) {
    const auto r = parseControlLine(
        R"({"cmd":"set_route","id":"r1","points":[[42.5,1.5],[42.51,1.51],[42.52,1.52]],)"
        R"("maneuvers":[{"index":1,"type":"roundabout","exit":3,"text":"CG-1"},{"index":2,"type":"roundabout"}]})");
    ASSERT_TRUE(r.command) << r.error;
    const auto& route = std::get<SetRouteCommand>(r.command->body);
    ASSERT_EQ(route.maneuvers.size(), 2U);
    EXPECT_EQ(route.maneuvers[0].type, ManeuverType::Roundabout);
    EXPECT_EQ(route.maneuvers[0].exit_number, 3U);
    EXPECT_EQ(route.maneuvers[0].text, "CG-1");
    EXPECT_FALSE(route.maneuvers[1].exit_number.has_value());
    const auto last = parseControlLine(
        R"({"cmd":"set_route","id":"r1","points":[[42.5,1.5],[42.51,1.51]],"maneuvers":[{"index":1,"type":"roundabout","exit":32}]})");
    ASSERT_TRUE(last.command) << last.error;
    EXPECT_EQ(std::get<SetRouteCommand>(last.command->body).maneuvers[0].exit_number, kMaxRoundaboutExit);
    EXPECT_FALSE(route.maneuvers[0].end_index.has_value());
    const auto ended =
        parseControlLine(R"({"cmd":"set_route","id":"r1","points":[[42.5,1.5],[42.51,1.51],[42.52,1.52]],)"
                         R"("maneuvers":[{"index":0,"end_index":2,"type":"roundabout","exit":1}]})");
    ASSERT_TRUE(ended.command) << ended.error;
    EXPECT_EQ(std::get<SetRouteCommand>(ended.command->body).maneuvers[0].end_index, 2U);
}

TEST(ControlProtocol, ParsesTheOtherCommands) {
    auto r = parseControlLine(R"({"cmd":"set_view","display":"cluster","mode":"snail","orientation":"north-up"})");
    ASSERT_TRUE(r.command) << r.error;
    const auto& v = std::get<SetViewCommand>(r.command->body);
    EXPECT_EQ(v.display, "cluster");
    EXPECT_EQ(v.mode, ViewMode::Snail);
    EXPECT_EQ(v.orientation, ViewOrientation::NorthUp);

    r = parseControlLine(R"({"cmd":"set_view","display":"hud","mode":"auto"})");
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_FALSE(std::get<SetViewCommand>(r.command->body).orientation);

    // A MapLibre-convention camera: zoom and pitch, optional bearing; null clears it.
    r = parseControlLine(R"({"cmd":"set_view","display":"cluster","camera":{"zoom":16.5,"pitch":60}})");
    ASSERT_TRUE(r.command) << r.error;
    {
        const auto& cv = std::get<SetViewCommand>(r.command->body);
        ASSERT_TRUE(cv.camera);
        EXPECT_DOUBLE_EQ(cv.camera->zoom, 16.5);
        EXPECT_DOUBLE_EQ(cv.camera->pitch_deg, 60.0);
        EXPECT_FALSE(cv.camera->bearing_deg);
        EXPECT_FALSE(cv.mode);
        EXPECT_FALSE(cv.clear_camera);
    }
    r = parseControlLine(
        R"({"cmd":"set_view","display":"hud","camera":{"zoom":0,"pitch":85,"bearing":-90},"orientation":"north-up"})");
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_EQ(std::get<SetViewCommand>(r.command->body).camera, (ViewCamera{0.0, 85.0, -90.0}));
    r = parseControlLine(R"({"cmd":"set_view","display":"hud","camera":null})");
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_TRUE(std::get<SetViewCommand>(r.command->body).clear_camera);
    EXPECT_FALSE(std::get<SetViewCommand>(r.command->body).camera);

    r = parseControlLine(R"({"cmd":"set_style","style":"night","id":"q7"})");
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_EQ(std::get<SetStyleCommand>(r.command->body).style, MapStyle::Night);
    EXPECT_EQ(r.command->request_id, "q7");
    EXPECT_FALSE(std::get<SetStyleCommand>(r.command->body).ground);  // unchanged
    r = parseControlLine(R"({"cmd":"set_style","ground":"orthoimage"})");
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_EQ(std::get<SetStyleCommand>(r.command->body).ground, Ground::Orthoimage);
    EXPECT_FALSE(std::get<SetStyleCommand>(r.command->body).style);
    r = parseControlLine(R"({"cmd":"set_style","style":"day","ground":"landcover"})");
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_EQ(std::get<SetStyleCommand>(r.command->body).style, MapStyle::Day);
    EXPECT_EQ(std::get<SetStyleCommand>(r.command->body).ground, Ground::LandCover);
    r = parseControlLine(R"({"cmd":"set_style","style":"auto"})");  // back to the sun or the lights
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_EQ(std::get<SetStyleCommand>(r.command->body).style, MapStyle::Auto);
    EXPECT_STREQ(mapStyleName(MapStyle::Auto), "auto");

    r = parseControlLine(R"({"cmd":"subscribe","events":["position_lost","position_regained"]})");
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_EQ(std::get<SubscribeCommand>(r.command->body).events, 6);
    r = parseControlLine(R"({"cmd":"subscribe","events":["off_route","back_on_route"]})");
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_EQ(std::get<SubscribeCommand>(r.command->body).events, 24);
    r = parseControlLine(R"({"cmd":"subscribe"})");
    ASSERT_TRUE(r.command) << r.error;
    EXPECT_EQ(std::get<SubscribeCommand>(r.command->body).events, kAllControlEvents);

    EXPECT_TRUE(parseControlLine(R"({"cmd":"get_status"})").command);
    EXPECT_TRUE(parseControlLine(R"(  {"cmd":"clear_route"}  )").command);
}

TEST(ControlProtocol, RepliesAndEventsHaveTheDocumentedShape) {
    EXPECT_EQ(controlOkReply("set_route", std::string("r1")), R"({"ok":true,"cmd":"set_route","id":"r1"})");
    EXPECT_EQ(controlErrorReply("set_route", std::nullopt, "points[3]: latitude 95 out of range [-90, 90]"),
              R"({"ok":false,"cmd":"set_route","error":"points[3]: latitude 95 out of range [-90, 90]"})");
    EXPECT_EQ(controlOkReply("get_status", std::nullopt, {{"status", {{"fps", 30}}}}),
              R"({"ok":true,"cmd":"get_status","status":{"fps":30}})");
    ControlEvent e;
    e.kind = ControlEventKind::RouteProgress;
    e.route_id = "r1";
    e.driven_m = 120.5;
    e.remaining_m = 3400.0;
    EXPECT_EQ(controlEventLine(e), R"({"event":"route_progress","id":"r1","driven_m":120.5,"remaining_m":3400.0})");
    e.kind = ControlEventKind::PositionLost;
    e.since_s = 2.0;
    EXPECT_EQ(controlEventLine(e), R"({"event":"position_lost","since_s":2.0})");
    e.kind = ControlEventKind::PositionRegained;
    EXPECT_EQ(controlEventLine(e), R"({"event":"position_regained"})");
    e = {};
    e.kind = ControlEventKind::OffRoute;
    e.route_id = "r7";
    e.offset_m = 57.26;
    EXPECT_EQ(controlEventLine(e), R"({"event":"off_route","id":"r7","offset_m":57.3})");
    e.kind = ControlEventKind::BackOnRoute;
    EXPECT_EQ(controlEventLine(e), R"({"event":"back_on_route","id":"r7"})");
    e = {};
    e.kind = ControlEventKind::GpuReset;
    e.resets = 2;
    EXPECT_EQ(controlEventLine(e), R"({"event":"gpu_reset","resets":2})");
}

struct BadCase {
    const char* line;
    const char* error;  // exact expected error
};

TEST(ControlProtocol, EveryMalformedRequestGetsAnErrorNamingTheProblem) {
    const BadCase cases[] = {
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4],[5,6],[95,1]]})",
         "points[3]: latitude 95 out of range [-90, 90]"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,-180.5]]})",
         "points[1]: longitude -180.5 out of range [-180, 180]"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2]]})", "\"points\" needs at least 2 points, got 1"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3]]})", "points[1]: must be [lat, lon]"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],["3",4]]})",
         "points[1]: latitude and longitude must be numbers"},
        {R"({"cmd":"set_route","id":"r1","points":{}})", "\"points\" must be an array of [lat, lon], not object"},
        {R"({"cmd":"set_route","points":[[1,2],[3,4]]})", "missing \"id\""},
        {R"({"cmd":"set_route","id":"","points":[[1,2],[3,4]]})", "\"id\" must not be empty"},
        {R"({"cmd":"set_route","id":7,"points":[[1,2],[3,4]]})", "\"id\" must be a string, not number"},
        {R"({"cmd":"set_route","id":"r1"})", "missing \"points\""},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"maneuvers":[{"index":2,"type":"turn_left"}]})",
         "maneuvers[0].index: 2 out of range [0, 1]"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"maneuvers":[{"index":-1,"type":"turn_left"}]})",
         "maneuvers[0].index: -1 out of range [0, 1]"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"maneuvers":[{"index":1,"type":"turn_left"},{"index":0,"type":"arrive"}]})",
         "maneuvers[1].index: 0 is before the previous maneuver's index 1"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"maneuvers":[{"index":0,"type":"fly"}]})",
         "maneuvers[0].type: unknown maneuver \"fly\" (expected one of depart | arrive | straight | turn_left | "
         "turn_right | slight_left | slight_right | sharp_left | sharp_right | u_turn | keep_left | keep_right | "
         "roundabout | exit | merge)"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"maneuvers":[{"index":0.5,"type":"exit"}]})",
         "maneuvers[0].index: must be an integer"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"extra":1})", "unknown field \"extra\""},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"maneuvers":[{"index":0,"type":"turn_left","exit":2}]})",
         "maneuvers[0].exit: only a roundabout maneuver has an exit number, not \"turn_left\""},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"maneuvers":[{"index":0,"type":"roundabout","exit":0}]})",
         "maneuvers[0].exit: 0 out of range [1, 32]"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"maneuvers":[{"index":0,"type":"roundabout","exit":-2}]})",
         "maneuvers[0].exit: -2 out of range [1, 32]"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"maneuvers":[{"index":0,"type":"roundabout","exit":33}]})",
         "maneuvers[0].exit: 33 out of range [1, 32]"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4]],"maneuvers":[{"index":0,"type":"roundabout","exit":"2"}]})",
         "maneuvers[0].exit: must be an integer"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4],[5,6]],"maneuvers":[{"index":1,"end_index":0,"type":"roundabout"}]})",
         "maneuvers[0].end_index: 0 out of range [1, 2]"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4],[5,6]],"maneuvers":[{"index":1,"end_index":3,"type":"roundabout"}]})",
         "maneuvers[0].end_index: 3 out of range [1, 2]"},
        {R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4],[5,6]],"maneuvers":[{"index":1,"end_index":1.5,"type":"roundabout"}]})",
         "maneuvers[0].end_index: must be an integer"},
        {R"({"cmd":"set_view","display":"cluster","mode":"helicopter"})",
         "\"mode\": \"helicopter\" is not one of bird | snail | auto"},
        {R"({"cmd":"set_view","display":"cluster","orientation":"up"})",
         "\"orientation\": \"up\" is not one of heading-up | north-up"},
        {R"({"cmd":"set_view","display":"cluster"})",
         "set_view needs \"mode\" (bird | snail | auto), \"orientation\" (heading-up | north-up) or \"camera\" "
         "({zoom, pitch[, bearing]} or null)"},
        {R"({"cmd":"set_view","display":"cluster","camera":"close"})",
         "\"camera\" must be an object {zoom, pitch[, bearing]} or null, not string"},
        {R"({"cmd":"set_view","display":"cluster","camera":{"zoom":16}})", "camera: missing \"pitch\""},
        {R"({"cmd":"set_view","display":"cluster","camera":{"pitch":60}})", "camera: missing \"zoom\""},
        {R"({"cmd":"set_view","display":"cluster","camera":{"zoom":30,"pitch":60}})",
         "camera.zoom: 30 out of range [0, 24]"},
        {R"({"cmd":"set_view","display":"cluster","camera":{"zoom":-1,"pitch":60}})",
         "camera.zoom: -1 out of range [0, 24]"},
        {R"({"cmd":"set_view","display":"cluster","camera":{"zoom":16,"pitch":85.5}})",
         "camera.pitch: 85.5 out of range [0, 85]"},
        {R"({"cmd":"set_view","display":"cluster","camera":{"zoom":16,"pitch":"60"}})",
         "camera.pitch: must be a number, not string"},
        {R"({"cmd":"set_view","display":"cluster","camera":{"zoom":16,"pitch":60,"bearing":400}})",
         "camera.bearing: 400 out of range [-360, 360]"},
        {R"({"cmd":"set_view","display":"cluster","camera":{"zoom":16,"pitch":60,"roll":5}})",
         "camera: unknown field \"roll\""},
        {R"({"cmd":"set_view","display":"cluster","mode":"bird","camera":[16,60]})",
         "\"camera\" must be an object {zoom, pitch[, bearing]} or null, not array"},
        {R"({"cmd":"set_view","mode":"bird"})", "missing \"display\""},
        {R"({"cmd":"set_style","style":"dusk"})", "\"style\": \"dusk\" is not one of day | night | auto"},
        {R"({"cmd":"set_style"})",
         "set_style needs \"style\" (day | night | auto) or \"ground\" (landcover | orthoimage)"},
        {R"({"cmd":"set_style","ground":"satellite"})",
         "\"ground\": \"satellite\" is not one of landcover | orthoimage"},
        {R"({"cmd":"set_style","style":"day","ground":1})", "\"ground\": must be one of landcover | orthoimage"},
        {R"({"cmd":"subscribe","events":["everything"]})",
         "events[0]: not one of route_progress | position_lost | position_regained | off_route | back_on_route | "
         "gpu_reset"},
        {R"({"cmd":"subscribe","events":[]})",
         "\"events\" must be a non-empty array of route_progress | position_lost | position_regained | off_route | "
         "back_on_route | gpu_reset"},
        {R"({"cmd":"get_status","verbose":true})", "unknown field \"verbose\""},
        {R"({"cmd":"reboot"})",
         "unknown cmd \"reboot\" (expected set_route | clear_route | set_view | set_style | get_status | subscribe)"},
        {R"({"cmd":42})", "\"cmd\" must be a string, not number"},
        {R"({"points":[]})", "missing \"cmd\""},
        {R"([1,2,3])", "request must be a JSON object, not array"},
        {R"("set_route")", "request must be a JSON object, not string"},
    };
    for (const auto& c : cases) {
        const auto r = parseControlLine(c.line);
        EXPECT_FALSE(r.command) << c.line;
        EXPECT_EQ(r.error, c.error) << c.line;
    }
    // The reply of the issue's example.
    const auto r = parseControlLine(R"({"cmd":"set_route","id":"r1","points":[[1,2],[3,4],[5,6],[95,1]]})");
    EXPECT_EQ(controlErrorReply(r.cmd, std::nullopt, r.error),
              R"({"ok":false,"cmd":"set_route","error":"points[3]: latitude 95 out of range [-90, 90]"})");
}

TEST(ControlProtocol, BrokenJsonAndLimits) {
    auto r = parseControlLine(R"({"cmd":"set_route",)");
    EXPECT_FALSE(r.command);
    EXPECT_EQ(r.error,
              "invalid JSON: parse error at line 1, column 20: syntax error while parsing object key - "
              "unexpected end of input; expected string literal");

    r = parseControlLine(std::string(100, '[') + std::string(100, ']'));
    EXPECT_EQ(r.error, "JSON nested deeper than 32 levels");

    ControlLimits limits;
    limits.max_route_points = 3;
    r = parseControlLine(R"({"cmd":"set_route","id":"r","points":[[1,2],[1,2],[1,2],[1,2]]})", limits);
    EXPECT_EQ(r.error, "\"points\" has 4 points, more than the limit of 3");
    limits.max_line_bytes = 10;
    r = parseControlLine(R"({"cmd":"get_status"})", limits);
    EXPECT_EQ(r.error, "line longer than 10 bytes");
    r = parseControlLine("{\"cmd\":\"set_style\",\"style\":\"\xff\"}");
    EXPECT_FALSE(r.command);
    EXPECT_NE(r.error.find("invalid JSON"), std::string::npos) << r.error;
    // An id that can be read is echoed even when the request fails.
    r = parseControlLine(R"({"cmd":"set_style","id":"q1","style":"dusk"})");
    EXPECT_EQ(r.id, "q1");
    EXPECT_EQ(r.cmd, "set_style");
}

TEST(ControlProtocol, DuplicateKeysAreRejectedAtEveryLevel) {
    struct Dup {
        const char* line;
        const char* error;
        const char* cmd;  // echoed cmd ("" = none)
        const char* id;   // echoed id (nullptr = none)
    };
    const Dup cases[] = {
        // The parser alone would keep the last "cmd": this line would clear the route.
        {R"({"cmd":"get_status","cmd":"clear_route"})", R"(duplicate key "cmd")", "", nullptr},
        // Keys compare after unescaping.
        {R"({"cmd":"get_status","\u0063md":"clear_route"})", R"(duplicate key "cmd")", "", nullptr},
        {R"({"cmd":"set_style","id":"a","style":"day","id":"b"})", R"(duplicate key "id")", "set_style", nullptr},
        {R"({"cmd":"set_style","id":"q","style":"day","style":"night"})", R"(duplicate key "style")", "set_style", "q"},
        // Inside a route point given as an object, and inside a maneuver.
        {R"({"cmd":"set_route","id":"r","points":[[1,2],{"lat":1,"lat":2}]})", R"(points[1]: duplicate key "lat")",
         "set_route", "r"},
        {R"({"cmd":"set_route","id":"r","points":[[1,2],[3,4]],"maneuvers":[{"index":0,"type":"depart"},)"
         R"({"index":1,"type":"arrive","text":"x","text":"y"}]})",
         R"(maneuvers[1]: duplicate key "text")", "set_route", "r"},
        // Deeper: an object in an array in an object in an array.
        {R"({"cmd":"subscribe","events":[{"a":[{"b":1,"b":2}]}]})", R"(events[0].a[0]: duplicate key "b")", "subscribe",
         nullptr},
    };
    for (const auto& c : cases) {
        const auto r = parseControlLine(c.line);
        EXPECT_FALSE(r.command) << c.line;
        EXPECT_EQ(r.error, c.error) << c.line;
        EXPECT_EQ(r.cmd, c.cmd) << c.line;
        EXPECT_EQ(r.id, c.id ? std::optional<std::string>(c.id) : std::nullopt) << c.line;
    }
    EXPECT_EQ(
        controlErrorReply(parseControlLine(cases[0].line).cmd, std::nullopt, parseControlLine(cases[0].line).error),
        R"({"ok":false,"error":"duplicate key \"cmd\""})");
    // The same key in different objects is fine.
    const auto ok = parseControlLine(
        R"({"cmd":"set_route","id":"r","points":[[1,2],[3,4]],"maneuvers":[{"index":0,"type":"depart","text":"a"},)"
        R"({"index":1,"type":"arrive","text":"b"}]})");
    ASSERT_TRUE(ok.command) << ok.error;
    EXPECT_EQ(std::get<SetRouteCommand>(ok.command->body).maneuvers.at(1).text, "b");
}
