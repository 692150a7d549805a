// SPDX-License-Identifier: Apache-2.0
#include "frame_annotator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "navmap/map/turn_lanes.h"
#include "route_guidance.h"

namespace navmap::daemon {
namespace {

std::int64_t realtimeNsOf(ipc::CanTime t) {
    return t == ipc::CanTime{} ? 0 : std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

}  // namespace

std::uint8_t metaLaneBits(std::uint16_t arrows, bool recommended) {
    namespace la = map::lane_arrow;
    // Block version 1 has six directions: sharp turns are sent as turns, a lane merging away as
    // the slight turn its traffic makes (docs/frame-protocol.md "Metadata block").
    std::uint8_t bits = 0;
    if (arrows & (la::kLeft | la::kSharpLeft)) bits |= ipc::kLaneLeft;
    if (arrows & (la::kSlightLeft | la::kMergeToLeft)) bits |= ipc::kLaneSlightLeft;
    if (arrows & la::kThrough) bits |= ipc::kLaneStraight;
    if (arrows & (la::kSlightRight | la::kMergeToRight)) bits |= ipc::kLaneSlightRight;
    if (arrows & (la::kRight | la::kSharpRight)) bits |= ipc::kLaneRight;
    if (arrows & la::kReverse) bits |= ipc::kLaneUTurn;
    if (recommended) bits |= ipc::kLaneRecommended;
    return bits;
}

ipc::FrameValidity frameValidity(const EstimatedPose& pose, const FrameHealth& health, bool off_route,
                                 std::size_t tiles_missing, std::size_t tiles_failed) {
    ipc::FrameValidity v;
    v.version = ipc::kFrameValidityVersion;
    const double age_ms = pose.valid ? pose.since_fix_s * 1000.0 : -1.0;
    v.pose_age_ms = age_ms < 0.0 || !std::isfinite(age_ms)
                        ? ipc::kPoseAgeNone
                        : static_cast<std::uint32_t>(std::min(age_ms, double(ipc::kPoseAgeNone - 1)));
    // On the whole milliseconds sent, so that a frame is stale exactly when its age says so;
    // following a tunnel's road without fixes the position is known (docs/vehicle-state.md "Tunnels").
    const bool follows_tunnel = pose.valid && pose.follows_graph && !pose.stale;
    if (v.pose_age_ms == ipc::kPoseAgeNone ||
        (v.pose_age_ms > static_cast<std::uint32_t>(health.stale_pose_ms) && !follows_tunnel))
        v.flags |= ipc::kValidityStalePose;
    if (tiles_missing > 0) v.degraded |= ipc::kDegradedTilesMissing;
    if (tiles_failed > 0) v.degraded |= ipc::kDegradedTilesFailed;
    if (health.road_graph_off) v.degraded |= ipc::kDegradedRoadGraphOff;
    if (health.orthoimage_off) v.degraded |= ipc::kDegradedOrthoimageOff;
    if (v.degraded != 0) v.flags |= ipc::kValidityDegraded;
    if (off_route) v.flags |= ipc::kValidityOffRoute;
    return v;
}

FrameAnnotation FrameAnnotator::annotate(const EstimatedPose& pose, const FrameHealth& health,
                                         const GuidanceSnapshot* guidance, const map::Projection& projection,
                                         const render::MapFrame& frame, const render::LodSelection& selection,
                                         const map::TileCache& cache) {
    // Tiles the camera wants and does not have: still loading, or never (corrupt, never retried).
    std::size_t failed = 0;
    if (!selection.wanted.empty()) {
        const auto corrupt = cache.corruptTiles();
        for (const auto& w : selection.wanted)
            if (std::find(corrupt.begin(), corrupt.end(), w.id) != corrupt.end()) ++failed;
    }
    const bool off_route = guidance != nullptr && guidance->off_route;
    FrameAnnotation a;
    a.validity = frameValidity(pose, health, off_route, selection.wanted.size() - failed, failed);

    ipc::FrameMeta m;
    m_frame_street = {};
    if (pose.valid) {
        m.has_pose = true;
        projection.reverse({pose.x, pose.y}, m.lat_deg, m.lon_deg);
        m.heading_deg = pose.heading_deg;
        m.pose_time_ns = realtimeNsOf(pose.time);  // the moment the pose was estimated for
        if (health.graph != nullptr && pose.edge && *pose.edge < health.graph->edges.size()) {
            m_frame_street = streetOf(health.graph->edges[*pose.edge].way_id, frame);
            m.current_street = m_frame_street.name.empty() ? m_frame_street.ref : m_frame_street.name;
        }
        // The matched road's limit in the driving direction; 0 (unknown) when the match is uncertain.
        m.speed_limit_kmh = static_cast<std::uint16_t>(std::clamp(pose.speed_limit_kmh, 0, 0xFFFF));
    }
    if (guidance != nullptr && guidance->active) {
        m.has_remaining = true;
        m.remaining_m = guidance->remaining_m;
        m.remaining_s = guidance->remaining_s;
        if (guidance->next && !off_route) {
            m.has_next = true;
            m.next_type = static_cast<std::uint8_t>(guidance->next->type);
            m.next_exit = static_cast<std::uint8_t>(std::clamp(guidance->next->exit, 0, 255));
            m.next_distance_m = guidance->next_distance_m;
            m.next_street = guidance->street;
            // The lanes before it where the road has turn lanes; else "unknown" (lanes_known false).
            if (guidance->lanes && !guidance->lanes->lanes.empty()) {
                m.lanes_known = true;
                const auto& lanes = guidance->lanes->lanes;
                for (std::size_t i = 0; i < lanes.size() && i < ipc::kMaxLanes; ++i)
                    m.lanes.push_back(metaLaneBits(lanes[i], (guidance->lanes->recommended >> i & 1U) != 0));
            }
        }
    }
    a.meta = std::make_shared<const std::vector<std::uint8_t>>(ipc::encodeFrameMeta(m));
    return a;
}

const render::StreetBar& FrameAnnotator::streetOf(std::int64_t way, const render::MapFrame& frame) {
    // Looked up again only when the way or the drawn tiles change (a road not found is not
    // searched for again every frame).
    const map::Tile* newest = frame.tiles.empty() ? nullptr : frame.tiles.back().get();
    if (way == m_way && frame.tiles.size() == m_tiles && newest == m_newest_tile) return m_street;
    m_way = way;
    m_tiles = frame.tiles.size();
    m_newest_tile = newest;
    m_street = {};
    // Every road of a leaf tile keeps its name and ref; coarser tiles may have dropped a small
    // road: then the street stays unknown until a tile that has it is drawn.
    bool found = false;
    for (auto it = frame.tiles.rbegin(); it != frame.tiles.rend() && !found; ++it) {
        for (const auto& road : (*it)->roads) {
            if (road.osm_id != way || (road.name.empty() && road.ref.empty())) continue;
            m_street = {road.name, road.ref};
            found = true;
            break;
        }
    }
    return m_street;
}

}  // namespace navmap::daemon
