// SPDX-License-Identifier: Apache-2.0
// Guidance manoeuvres: turn classes at their boundaries, manoeuvres derived on synthetic
// junctions (choice or none, forks, straight on where the road turns away) and on a synthetic
// roundabout (exit numbers counted from the entry, entered and left as one manoeuvre).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "guidance_test_graph.h"
#include "navmap/map/guidance/maneuver_derivation.h"

namespace navmap::map::guidance {
namespace {

using test::TestGraph;

PlanarPoint polar(double heading_deg, double r, PlanarPoint c = {0, 0}) {
    const double a = heading_deg * std::numbers::pi / 180.0;
    return {c.x + r * std::sin(a), c.y + r * std::cos(a)};
}

std::vector<std::string> typesOf(const std::vector<Maneuver>& ms) {
    std::vector<std::string> out;
    out.reserve(ms.size());
    for (const auto& m : ms) out.emplace_back(maneuverTypeName(m.type));
    return out;
}

TEST(GuidanceTurnClass, BoundariesOnBothSides) {
    EXPECT_EQ(classifyTurn(0.0), ManeuverType::Straight);
    EXPECT_EQ(classifyTurn(19.9), ManeuverType::Straight);
    EXPECT_EQ(classifyTurn(-19.9), ManeuverType::Straight);
    EXPECT_EQ(classifyTurn(20.0), ManeuverType::SlightRight);
    EXPECT_EQ(classifyTurn(-20.0), ManeuverType::SlightLeft);
    EXPECT_EQ(classifyTurn(44.9), ManeuverType::SlightRight);
    EXPECT_EQ(classifyTurn(45.0), ManeuverType::TurnRight);
    EXPECT_EQ(classifyTurn(-45.0), ManeuverType::TurnLeft);
    EXPECT_EQ(classifyTurn(134.9), ManeuverType::TurnRight);
    EXPECT_EQ(classifyTurn(135.0), ManeuverType::SharpRight);
    EXPECT_EQ(classifyTurn(-135.0), ManeuverType::SharpLeft);
    EXPECT_EQ(classifyTurn(169.9), ManeuverType::SharpRight);
    EXPECT_EQ(classifyTurn(170.0), ManeuverType::UTurn);
    EXPECT_EQ(classifyTurn(-180.0), ManeuverType::UTurn);
    EXPECT_EQ(classifyTurn(std::nan("")), ManeuverType::Straight);
    TurnThresholds wide;
    wide.straight_deg = 30.0;
    EXPECT_EQ(classifyTurn(25.0, wide), ManeuverType::Straight);
}

TEST(GuidanceTurnClass, HeadingChangeWrapsAndNamesMatchTheProtocol) {
    EXPECT_DOUBLE_EQ(headingChange(350.0, 10.0), 20.0);
    EXPECT_DOUBLE_EQ(headingChange(10.0, 350.0), -20.0);
    EXPECT_DOUBLE_EQ(headingChange(-170.0, 170.0), -20.0);
    EXPECT_EQ(maneuverTypeName(ManeuverType::SharpLeft), "sharp_left");
    EXPECT_EQ(maneuverTypeName(ManeuverType::UTurn), "u_turn");
    for (std::size_t i = 0; i < kManeuverTypeCount; ++i) {
        const auto t = static_cast<ManeuverType>(i);
        EXPECT_EQ(maneuverTypeFromName(maneuverTypeName(t)), t);
    }
    EXPECT_FALSE(maneuverTypeFromName("turn_around").has_value());
}

// A junction at the origin reached from the south (heading north); arms leave it at the given
// headings (clockwise from north), 100 m long, each its own way. The route goes to arm 0.
std::vector<Maneuver> viaJunction(const std::vector<double>& arms, std::uint8_t arm0_flags = 0,
                                  RoadClass other_class = RoadClass::Residential) {
    TestGraph t;
    const auto south = t.node(0, -100);
    const auto c = t.node(0, 0);
    t.way(1, {south, c});
    std::uint32_t target = 0;
    for (std::size_t k = 0; k < arms.size(); ++k) {
        const PlanarPoint p = polar(arms[k], 100.0);
        const auto n = t.node(p.x, p.y);
        if (k == 0) target = n;
        t.way(static_cast<std::int64_t>(10 + k), {c, n}, k == 0 ? RoadClass::Residential : other_class,
              k == 0 ? arm0_flags : 0);
    }
    const RoadGraph g = t.build();
    return deriveManeuvers(g, test::routeLine(g, south, target));
}

TEST(GuidanceManeuvers, TurnClassesOnASyntheticJunction) {
    struct Case {
        double arm;
        double other;
        const char* type;
    };
    for (const Case& c : std::vector<Case>{{30, -100, "slight_right"},
                                           {-30, 100, "slight_left"},
                                           {60, -90, "turn_right"},
                                           {90, -90, "turn_right"},
                                           {-120, 90, "turn_left"},
                                           {150, -60, "sharp_right"},
                                           {-160, 60, "sharp_left"},
                                           {175, 60, "u_turn"}}) {
        const auto ms = viaJunction({c.arm, c.other});
        ASSERT_EQ(ms.size(), 3U) << c.arm;
        EXPECT_EQ(typesOf(ms), (std::vector<std::string>{"depart", c.type, "arrive"})) << c.arm;
        EXPECT_NEAR(ms[1].turn_deg, c.arm, 0.5) << c.arm;
        EXPECT_EQ(ms[1].point, 1U);
        EXPECT_NEAR(ms[1].measure_m, 100.0, 1e-3);
        EXPECT_EQ(ms[1].exit, 0);
    }
}

TEST(GuidanceManeuvers, NoChoiceNoManeuverHoweverTheRoadBends) {
    // A 90-degree bend where two ways meet, and one with a footway as the third arm: a driver
    // has nowhere else to go.
    EXPECT_EQ(typesOf(viaJunction({90})), (std::vector<std::string>{"depart", "arrive"}));
    EXPECT_EQ(typesOf(viaJunction({-90, 90}, 0, RoadClass::Path)), (std::vector<std::string>{"depart", "arrive"}));
    // A one-way arm that only leads into the junction is no choice either.
    TestGraph t;
    const auto s = t.node(0, -100), c = t.node(0, 0), e = t.node(100, 0), w = t.node(-100, 0);
    t.way(1, {s, c});
    t.way(2, {c, e});
    t.way(3, {w, c}, RoadClass::Residential, road_flags::kOneway);
    const RoadGraph g = t.build();
    EXPECT_EQ(typesOf(deriveManeuvers(g, test::routeLine(g, s, e))), (std::vector<std::string>{"depart", "arrive"}));
}

TEST(GuidanceManeuvers, StraightOverACrossingIsSilentStraightOffATurningRoadIsNot) {
    // Crossing other roads straight on: nothing to say.
    EXPECT_EQ(typesOf(viaJunction({5, 90, -90})), (std::vector<std::string>{"depart", "arrive"}));
    // The way the route arrives on turns right; the route goes straight on another road.
    TestGraph t;
    const auto s = t.node(0, -100), c = t.node(0, 0), n = t.node(0, 100), e = t.node(100, 0);
    t.way(1, {s, c, e});  // one OSM way through the junction
    t.way(2, {c, n});
    const RoadGraph g = t.build();
    const auto ms = deriveManeuvers(g, test::routeLine(g, s, n));
    EXPECT_EQ(typesOf(ms), (std::vector<std::string>{"depart", "straight", "arrive"}));
    // Following that way round its bend: the road goes on, the straight one is the choice.
    const auto follow = deriveManeuvers(g, test::routeLine(g, s, e));
    EXPECT_EQ(typesOf(follow), (std::vector<std::string>{"depart", "turn_right", "arrive"}));
}

TEST(GuidanceManeuvers, FollowingABendingRoadPastASideStreetIsSilent) {
    TestGraph t;
    const auto s = t.node(0, -100), c = t.node(0, 0);
    const PlanarPoint p = polar(-30, 100.0);
    const auto on = t.node(p.x, p.y), side = t.node(100, 0);
    t.way(1, {s, c, on});  // bends 30 degrees left at the junction
    t.way(2, {c, side});
    const RoadGraph g = t.build();
    EXPECT_EQ(typesOf(deriveManeuvers(g, test::routeLine(g, s, on))), (std::vector<std::string>{"depart", "arrive"}));
    EXPECT_EQ(typesOf(deriveManeuvers(g, test::routeLine(g, s, side))),
              (std::vector<std::string>{"depart", "turn_right", "arrive"}));
}

TEST(GuidanceManeuvers, ForksAreKeepLeftAndKeepRight) {
    EXPECT_EQ(typesOf(viaJunction({20, -15})), (std::vector<std::string>{"depart", "keep_right", "arrive"}));
    EXPECT_EQ(typesOf(viaJunction({-15, 20})), (std::vector<std::string>{"depart", "keep_left", "arrive"}));
    // Three near-straight branches: the middle one is straight on.
    EXPECT_EQ(typesOf(viaJunction({0, -30, 30})), (std::vector<std::string>{"depart", "straight", "arrive"}));
    // A motorway exit at 25 degrees: staying on the motorway (the same way) needs no word,
    // taking the ramp is keep_right.
    TestGraph t;
    const auto s = t.node(0, -300), c = t.node(0, 0), n = t.node(0, 300);
    const PlanarPoint p = polar(25, 200.0);
    const auto ramp = t.node(p.x, p.y);
    t.way(1, {s, c, n}, RoadClass::Motorway, road_flags::kOneway);
    t.way(2, {c, ramp}, RoadClass::Motorway, road_flags::kOneway | road_flags::kLink);
    const RoadGraph g = t.build();
    EXPECT_EQ(typesOf(deriveManeuvers(g, test::routeLine(g, s, n))), (std::vector<std::string>{"depart", "arrive"}));
    EXPECT_EQ(typesOf(deriveManeuvers(g, test::routeLine(g, s, ramp))),
              (std::vector<std::string>{"depart", "keep_right", "arrive"}));
}

TEST(GuidanceManeuvers, StreetNamesComeFromTheWaysAndJoinSplitWays) {
    TestGraph t;
    const auto s = t.node(0, -100), c = t.node(0, 0), e = t.node(100, 0), n = t.node(0, 100);
    t.way(1, {s, c});
    t.way(2, {c, n});  // the same street, split at the junction
    t.way(3, {c, e});
    const RoadGraph g = t.build();
    WayNames names;
    names.add(1, "Avinguda Meritxell", "");
    names.add(2, "Avinguda Meritxell", "CG-1");
    names.add(3, "", "CS-101");
    // Without names the split looks like leaving the road; with them it is the same street.
    EXPECT_EQ(typesOf(deriveManeuvers(g, test::routeLine(g, s, n), &names)),
              (std::vector<std::string>{"depart", "arrive"}));
    const auto ms = deriveManeuvers(g, test::routeLine(g, s, e), &names);
    ASSERT_EQ(typesOf(ms), (std::vector<std::string>{"depart", "turn_right", "arrive"}));
    EXPECT_EQ(ms[0].street, "Avinguda Meritxell");
    EXPECT_EQ(ms[1].street, "CS-101");  // no name: the ref
    EXPECT_EQ(names.lookup(99), "");
}

// A counter-clockwise roundabout of radius 30 m (right-hand traffic) with ring nodes at the
// given headings from its centre, each with a two-way arm of 100 m outwards; `entry_only`
// headings get a one-way arm into the ring (not an exit) and `footway` headings a footway.
struct Roundabout {
    RoadGraph graph;
    std::vector<std::uint32_t> arm_end;  // per ring node, the arm's outer node
};

Roundabout roundabout(const std::vector<double>& exits, const std::vector<double>& entry_only,
                      const std::vector<double>& footways) {
    struct Arm {
        double heading;
        int kind;  // 0 two-way, 1 entry only, 2 footway
    };
    std::vector<Arm> arms;
    arms.reserve(exits.size() + entry_only.size() + footways.size());
    for (double h : exits) arms.push_back({h, 0});
    for (double h : entry_only) arms.push_back({h, 1});
    for (double h : footways) arms.push_back({h, 2});
    // Counter-clockwise: decreasing compass heading.
    std::sort(arms.begin(), arms.end(), [](const Arm& a, const Arm& b) { return a.heading > b.heading; });
    TestGraph t;
    std::vector<std::uint32_t> ring;
    for (const Arm& a : arms) {
        const PlanarPoint p = polar(a.heading, 30.0);
        ring.push_back(t.node(p.x, p.y));
    }
    Roundabout r;
    std::int64_t id = 100;
    for (std::size_t k = 0; k < arms.size(); ++k) {
        const double h0 = arms[k].heading;
        double h1 = arms[(k + 1) % arms.size()].heading;
        if (h1 >= h0) h1 -= 360.0;
        std::vector<PlanarPoint> arc;
        for (double h = h0 - 10.0; h > h1 + 1.0; h -= 10.0) arc.push_back(polar(h, 30.0));
        t.way(id++, {ring[k], ring[(k + 1) % arms.size()]}, RoadClass::Secondary,
              road_flags::kOneway | road_flags::kRoundabout, {arc});
        const PlanarPoint o = polar(arms[k].heading, 130.0);
        const auto outer = t.node(o.x, o.y);
        if (arms[k].kind == 0) {
            t.way(id++, {ring[k], outer});
            r.arm_end.push_back(outer);
        } else if (arms[k].kind == 1) {
            t.way(id++, {outer, ring[k]}, RoadClass::Residential, road_flags::kOneway);
        } else {
            t.way(id++, {ring[k], outer}, RoadClass::Path);
        }
    }
    r.graph = t.build();
    return r;
}

TEST(GuidanceManeuvers, RoundaboutExitNumbersCountFromTheEntry) {
    // Exits at 180 (the entry, south), 90 (east), 0 (north), 270 (west); counter-clockwise from
    // the south the east exit comes first.
    const Roundabout r = roundabout({180, 90, 0, 270}, {}, {});
    // arm_end is in ring order from the largest heading: 270, 180, 90, 0.
    const std::uint32_t west = r.arm_end[0], south = r.arm_end[1], east = r.arm_end[2], north = r.arm_end[3];
    struct Case {
        std::uint32_t to;
        int exit;
        ManeuverType turn;
    };
    for (const Case& c : std::vector<Case>{{east, 1, ManeuverType::TurnRight},
                                           {north, 2, ManeuverType::Straight},
                                           {west, 3, ManeuverType::TurnLeft}}) {
        const auto line = test::routeLine(r.graph, south, c.to);
        ASSERT_FALSE(line.empty());
        const auto ms = deriveManeuvers(r.graph, line);
        ASSERT_EQ(typesOf(ms), (std::vector<std::string>{"depart", "roundabout", "arrive"})) << c.exit;
        const Maneuver& m = ms[1];
        EXPECT_EQ(m.exit, c.exit);
        EXPECT_EQ(classifyTurn(m.turn_deg), c.turn) << m.turn_deg;
        // Entered at the ring node 100 m from the start, left at the exit's ring node.
        EXPECT_NEAR(m.measure_m, 100.0, 1e-3);
        EXPECT_GT(m.end_point, m.point);
        EXPECT_NEAR(line[m.end_point].position.x, polar(c.exit == 1 ? 90 : c.exit == 2 ? 0 : 270, 30.0).x, 0.01);
        EXPECT_GT(m.end_measure_m, m.measure_m + 30.0);
    }
}

TEST(GuidanceManeuvers, RoundaboutEntriesAndFootwaysAreNotExits) {
    // A one-way entry at 135 and a footway at 45 lie between the entry and the east exit.
    const Roundabout r = roundabout({180, 90, 0}, {135}, {45});
    const std::uint32_t south = r.arm_end[0], east = r.arm_end[1], north = r.arm_end[2];
    auto exit_to = [&](std::uint32_t to) {
        const auto ms = deriveManeuvers(r.graph, test::routeLine(r.graph, south, to));
        return ms.size() == 3 && ms[1].type == ManeuverType::Roundabout ? ms[1].exit : -1;
    };
    EXPECT_EQ(exit_to(east), 1);
    EXPECT_EQ(exit_to(north), 2);
}

TEST(GuidanceManeuvers, ShortOrBrokenInputGivesNoJunctionManeuvers) {
    const RoadGraph empty;
    EXPECT_TRUE(deriveManeuvers(empty, {}).empty());
    std::vector<RoutePoint> line{{{0, 0}, 0.0, 7}, {{0, 10}, 10.0, 8}, {{0, 20}, 20.0, 9}};
    EXPECT_EQ(typesOf(deriveManeuvers(empty, line)), (std::vector<std::string>{"depart", "arrive"}));
}

}  // namespace
}  // namespace navmap::map::guidance
