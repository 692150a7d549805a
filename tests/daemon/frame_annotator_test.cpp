// SPDX-License-Identifier: Apache-2.0
// A frame's validity from the daemon's state (daemon/frame_annotator.h, docs/frame-protocol.md
// "Frame validity"): the pose's age against stale_pose_ms, each degraded reason, off route; and the
// map-matched way's name and ref for the metadata and the street bar.
#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "frame_annotator.h"
#include "navmap/map/tile_source.h"
#include "navmap/map/turn_lanes.h"
#include "route_guidance.h"

using namespace navmap;
using namespace navmap::daemon;

namespace {

EstimatedPose poseAged(double seconds) {
    EstimatedPose p;
    p.valid = true;
    p.since_fix_s = seconds;
    return p;
}

}  // namespace

TEST(FrameValidity, ThePoseAgeDecidesStalePoseAtTheConfiguredLimit) {
    FrameHealth health;
    health.stale_pose_ms = 1000;
    auto v = frameValidity(poseAged(0.2), health, false, 0, 0);
    EXPECT_EQ(v.version, ipc::kFrameValidityVersion);
    EXPECT_TRUE(v.fresh());
    EXPECT_EQ(v.pose_age_ms, 200U);
    v = frameValidity(poseAged(1.0), health, false, 0, 0);
    EXPECT_TRUE(v.fresh()) << "exactly the limit is not older than it";
    v = frameValidity(poseAged(1.2), health, false, 0, 0);
    EXPECT_EQ(v.flags, ipc::kValidityStalePose);
    EXPECT_EQ(v.pose_age_ms, 1200U);
    health.stale_pose_ms = 2000;
    EXPECT_TRUE(frameValidity(poseAged(1.2), health, false, 0, 0).fresh());
    // No fix yet: stale, with no age.
    v = frameValidity(EstimatedPose{}, health, false, 0, 0);
    EXPECT_EQ(v.flags, ipc::kValidityStalePose);
    EXPECT_EQ(v.pose_age_ms, ipc::kPoseAgeNone);
    // Following a tunnel's road without fixes (docs/vehicle-state.md "Tunnels"): the age goes on,
    // the flag stays off until the estimator itself calls the pose stale.
    health.stale_pose_ms = 1000;
    EstimatedPose tunnel = poseAged(30.0);
    tunnel.follows_graph = true;
    v = frameValidity(tunnel, health, false, 0, 0);
    EXPECT_TRUE(v.fresh());
    EXPECT_EQ(v.pose_age_ms, 30000U);
    tunnel.stale = true;  // out of the tunnel, still without a fix
    EXPECT_EQ(frameValidity(tunnel, health, false, 0, 0).flags, ipc::kValidityStalePose);
}

TEST(FrameValidity, EachDegradedReasonAndOffRouteAreTheirOwnBits) {
    FrameHealth health;
    auto v = frameValidity(poseAged(0.1), health, false, 3, 0);
    EXPECT_EQ(v.flags, ipc::kValidityDegraded);
    EXPECT_EQ(v.degraded, ipc::kDegradedTilesMissing);
    v = frameValidity(poseAged(0.1), health, false, 0, 1);
    EXPECT_EQ(v.degraded, ipc::kDegradedTilesFailed);
    health.road_graph_off = true;
    health.orthoimage_off = true;
    v = frameValidity(poseAged(0.1), health, true, 0, 0);
    EXPECT_EQ(v.flags, ipc::kValidityDegraded | ipc::kValidityOffRoute);
    EXPECT_EQ(v.degraded, ipc::kDegradedRoadGraphOff | ipc::kDegradedOrthoimageOff);
    EXPECT_EQ(ipc::validityText(v), "degraded+off_route");
    EXPECT_EQ(ipc::degradedText(v.degraded), "road_graph_off+orthoimage_off");
}

// The lanes in the metadata block (docs/frame-protocol.md "Metadata block"): block version 1's
// six directions and the recommended bit; sharp turns as turns, merges as the slight turn their
// traffic makes, a lane without arrows as no direction.
TEST(FrameMetaLanes, ArrowsAsTheBlockSendsThem) {
    namespace la = map::lane_arrow;
    EXPECT_EQ(metaLaneBits(la::kLeft, false), ipc::kLaneLeft);
    EXPECT_EQ(metaLaneBits(la::kSharpLeft, false), ipc::kLaneLeft);
    EXPECT_EQ(metaLaneBits(la::kSlightLeft, true), ipc::kLaneSlightLeft | ipc::kLaneRecommended);
    EXPECT_EQ(metaLaneBits(la::kThrough | la::kRight, true),
              ipc::kLaneStraight | ipc::kLaneRight | ipc::kLaneRecommended);
    EXPECT_EQ(metaLaneBits(la::kSharpRight | la::kSlightRight, false), ipc::kLaneRight | ipc::kLaneSlightRight);
    EXPECT_EQ(metaLaneBits(la::kReverse, false), ipc::kLaneUTurn);
    EXPECT_EQ(metaLaneBits(la::kMergeToLeft, false), ipc::kLaneSlightLeft);
    EXPECT_EQ(metaLaneBits(la::kMergeToRight, false), ipc::kLaneSlightRight);
    EXPECT_EQ(metaLaneBits(0, true), ipc::kLaneRecommended);
    EXPECT_EQ(metaLaneBits(0, false), 0);
    // Every combination stays within the bits a version 1 decoder knows.
    for (unsigned a = 0; a <= la::kKnown; ++a) {
        const std::uint8_t bits = metaLaneBits(static_cast<std::uint16_t>(a), (a & 1) != 0);
        ASSERT_EQ(bits & ~ipc::kLaneBitsKnown, 0) << a;
    }
}

namespace {

// A source with no tiles: the annotator only asks the cache which wanted tiles are corrupt.
class NoTiles : public map::TileSource {
public:
    [[nodiscard]] const map::TileScheme& scheme() const override { return m_scheme; }
    [[nodiscard]] bool contains(map::TileId) const override { return false; }
    [[nodiscard]] map::TileLoadResult load(map::TileId) const override { return {nullptr, "", true}; }
    [[nodiscard]] std::uint32_t demSamples() const override { return 0; }

private:
    map::TileScheme m_scheme{0, 0, 16000, 4};
};

std::shared_ptr<const map::Tile> tileWith(std::vector<map::Road> roads) {
    auto t = std::make_shared<map::Tile>();
    t->roads = std::move(roads);
    return t;
}

map::Road road(std::int64_t way, const char* name, const char* ref) {
    map::Road r;
    r.osm_id = way;
    r.name = name;
    r.ref = ref;
    return r;
}

}  // namespace

// The map-matched road's street (FrameAnnotator::street(), the street bar's): the way's name and
// ref kept apart, from the drawn tiles, the finest first; the metadata's current street is the
// name, else the ref; nothing without a valid pose or a matched edge.
TEST(FrameAnnotator, TheMatchedWaysNameAndRefFromTheDrawnTiles) {
    map::RoadGraph graph;
    graph.edges.resize(3);
    graph.edges[0].way_id = 11;
    graph.edges[1].way_id = 22;
    graph.edges[2].way_id = 33;
    FrameHealth health;
    health.graph = &graph;
    const map::Projection projection(42.5, 1.5);
    const map::TileCache cache(std::make_shared<NoTiles>());
    const render::LodSelection selection;
    render::MapFrame frame;
    // A coarse tile without way 22's ref, then a finer one with it.
    frame.tiles = {tileWith({road(22, "Avinguda Meritxell", "")}),
                   tileWith({road(11, "", "CG-2"), road(22, "Avinguda Meritxell", "CG-1")})};
    FrameAnnotator annotator;
    EstimatedPose pose;
    pose.valid = true;
    auto streetOf = [&](std::optional<std::uint32_t> edge) {
        pose.edge = edge;
        const FrameAnnotation a = annotator.annotate(pose, health, nullptr, projection, frame, selection, cache);
        const auto meta = ipc::decodeFrameMeta(a.meta->data(), a.meta->size());
        EXPECT_TRUE(meta);
        return std::pair(annotator.street(), meta ? meta.value().current_street : std::string("?"));
    };
    auto [street, meta] = streetOf(1);
    EXPECT_EQ(street, (render::StreetBar{"Avinguda Meritxell", "CG-1"}));
    EXPECT_EQ(meta, "Avinguda Meritxell");
    std::tie(street, meta) = streetOf(0);
    EXPECT_EQ(street, (render::StreetBar{"", "CG-2"}));
    EXPECT_EQ(meta, "CG-2");
    std::tie(street, meta) = streetOf(2);
    EXPECT_EQ(street, render::StreetBar{}) << "a way no drawn tile has";
    std::tie(street, meta) = streetOf(std::nullopt);
    EXPECT_EQ(street, render::StreetBar{}) << "no matched edge";
    std::tie(street, meta) = streetOf(7);
    EXPECT_EQ(street, render::StreetBar{}) << "an edge the graph does not have";
    pose.valid = false;
    std::tie(street, meta) = streetOf(1);
    EXPECT_EQ(street, render::StreetBar{}) << "no pose";
}

// The block of a frame drawn before a manoeuvre with lanes: the lanes left to right, the one to
// take recommended; off the route, or without lane data, "unknown".
TEST(FrameMetaLanes, TheNextManoeuvresLanesReachTheBlock) {
    namespace la = map::lane_arrow;
    const map::Projection projection(42.5, 1.5);
    map::TileCache cache(std::make_shared<NoTiles>());
    const render::MapFrame frame;
    const render::LodSelection selection;
    EstimatedPose pose = poseAged(0.1);
    GuidanceSnapshot g;
    g.active = true;
    map::guidance::Maneuver m;
    m.type = map::guidance::ManeuverType::TurnLeft;
    g.next = m;
    g.next_distance_m = 240.0;
    g.lanes = map::guidance::LaneGuidance{{la::kLeft, la::kThrough, 0}, 0b001, 0.0, 7};
    FrameAnnotator annotator;
    const auto decode = [&](const GuidanceSnapshot& s) {
        const auto a = annotator.annotate(pose, FrameHealth{}, &s, projection, frame, selection, cache);
        auto d = ipc::decodeFrameMeta(a.meta->data(), a.meta->size());
        EXPECT_TRUE(d) << d.error().message;
        return d ? d.value() : ipc::FrameMeta{};
    };
    const ipc::FrameMeta with = decode(g);
    ASSERT_TRUE(with.has_next);
    EXPECT_TRUE(with.lanes_known);
    EXPECT_EQ(with.lanes, (std::vector<std::uint8_t>{ipc::kLaneLeft | ipc::kLaneRecommended, ipc::kLaneStraight, 0}));
    GuidanceSnapshot off = g;
    off.off_route = true;
    EXPECT_FALSE(decode(off).lanes_known);
    GuidanceSnapshot none = g;
    none.lanes.reset();
    const ipc::FrameMeta unknown = decode(none);
    EXPECT_TRUE(unknown.has_next);
    EXPECT_FALSE(unknown.lanes_known);
    EXPECT_TRUE(unknown.lanes.empty());
}
