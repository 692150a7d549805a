// SPDX-License-Identifier: Apache-2.0
// navmap-ctl against an in-process ControlServer: prints the reply, exit status follows "ok",
// `subscribe --count N` prints events, usage errors exit 2, an error reply or no daemon exit 1.

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <future>
#include <string>
#include <thread>

#include "control_test_util.h"
#include "navmap/ipc/control/control_server.h"
#include "navmap/ipc/control/control_state.h"

using namespace navmap::ipc;
using namespace std::chrono_literals;

namespace {

struct RunResult {
    int status = -1;
    std::string out;
};

RunResult runCtl(const std::string& args) {
    RunResult r;
    const std::string cmd = std::string(NAVMAP_CTL_PATH) + " " + args + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (p == nullptr) {
        return r;
    }
    char buf[4096];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) {
        r.out.append(buf, n);
    }
    const int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

}  // namespace

TEST(NavmapCtl, SendsCommandsAndPrintsReplies) {
    navmap::test::TempDir dir;
    ControlState state({"cluster", "hud"});
    ControlServerConfig cfg;
    cfg.socket_path = dir.file("c.sock");
    auto server = ControlServer::create(cfg, state);
    ASSERT_TRUE(server.ok()) << server.error().message;
    ASSERT_TRUE(server.value()->start().ok());
    const std::string s = "--socket " + cfg.socket_path + " ";

    auto r = runCtl(s + "set_route r9 42.5075,1.5218 42.51,1.53 42.52,1.54");
    EXPECT_EQ(r.status, 0);
    EXPECT_EQ(r.out, "{\"ok\":true,\"cmd\":\"set_route\",\"id\":\"r9\",\"maneuvers\":0,\"points\":3}\n");
    ASSERT_NE(state.route(), nullptr);
    EXPECT_EQ(state.route()->points.size(), 3U);

    r = runCtl(s + "set_view cluster bird north-up");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(state.view()->displays.at("cluster").mode, ViewMode::Bird);
    EXPECT_EQ(state.view()->displays.at("cluster").orientation, ViewOrientation::NorthUp);

    r = runCtl(s + "set_style night orthoimage");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(state.view()->style, MapStyle::Night);
    EXPECT_EQ(state.view()->ground, Ground::Orthoimage);
    r = runCtl(s + "set_style landcover");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(state.view()->style, MapStyle::Night);
    EXPECT_EQ(state.view()->ground, Ground::LandCover);

    r = runCtl(s + "set_style dusk");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.out,
              "{\"ok\":false,\"cmd\":\"set_style\",\"error\":\"\\\"style\\\": \\\"dusk\\\" is not one of day | night | "
              "auto\"}\n");

    r = runCtl(s + "send '{\"cmd\":\"get_status\",\"id\":\"s1\"}'");
    EXPECT_EQ(r.status, 0);
    EXPECT_EQ(r.out.rfind("{\"ok\":true,\"cmd\":\"get_status\",\"id\":\"s1\",\"status\":{", 0), 0U) << r.out;

    auto events = std::async(std::launch::async,
                             [&] { return runCtl(s + "subscribe --count 2 position_lost position_regained"); });
    // Publish until the subscriber has had time to connect; it prints exactly two events.
    for (int i = 0; i < 100 && events.wait_for(50ms) != std::future_status::ready; ++i) {
        if (server.value()->stats().commands >= 4) {
            server.value()->publish({ControlEventKind::PositionLost, {}, 0, 0, 2.0});
        }
    }
    r = events.get();
    EXPECT_EQ(r.status, 0);
    EXPECT_EQ(r.out,
              "{\"ok\":true,\"cmd\":\"subscribe\",\"events\":[\"position_lost\",\"position_regained\"]}\n"
              "{\"event\":\"position_lost\",\"since_s\":2.0}\n{\"event\":\"position_lost\",\"since_s\":2.0}\n");

    r = runCtl(s + "set_route r1 1,2");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.out.find("set_route needs ID and at least two LAT,LON points"), std::string::npos);
    r = runCtl(s + "frobnicate");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.out.find("navmap-ctl: The following argument was not expected: frobnicate"), std::string::npos)
        << r.out;
    r = runCtl("--socket " + dir.file("none.sock") + " get_status");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.out, "navmap-ctl: connect(" + dir.file("none.sock") + "): No such file or directory\n");
}
