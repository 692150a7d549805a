// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameAnnotator: what each frame says about itself beside its pixels (docs/frame-protocol.md
// "Frame validity" and "Metadata block"), from the daemon's own state when the frame is drawn:
// the pose's age against [stream] stale_pose_ms, tiles the camera wants that are not resident or
// failed to load, the road graph and the orthoimage ground being off, the guidance's off-route
// state; and the metadata block: the pose used, the next manoeuvre and the lanes before it, what
// is left of the route, the map-matched road's name. One per display; render thread only, never waits.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "navmap/daemon/vehicle/vehicle_state.h"
#include "navmap/ipc/client/frame_meta.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"
#include "navmap/map/tile_cache.h"
#include "navmap/render/map_frame.h"
#include "navmap/render/terrain_lod.h"

namespace navmap::daemon {

struct GuidanceSnapshot;

/// What the daemon knows of its own health each tick (the same for every display).
struct FrameHealth {
    int stale_pose_ms = 1000;               ///< [stream] stale_pose_ms
    bool road_graph_off = false;            ///< the store's road graph did not load
    bool orthoimage_off = false;            ///< the orthoimage ground is asked for and not drawn
    const map::RoadGraph* graph = nullptr;  ///< for the matched edge's way (null: none)
};

/// A frame's validity and metadata block, kept with the frame until it is published.
struct FrameAnnotation {
    ipc::FrameValidity validity;
    std::shared_ptr<const std::vector<std::uint8_t>> meta;
};

class FrameAnnotator {
public:
    /// `pose`: the estimate the frame was drawn with; `frame`: its drawn tiles; `selection`:
    /// the tiles its camera wants; `guidance`: may be null.
    FrameAnnotation annotate(const EstimatedPose& pose, const FrameHealth& health, const GuidanceSnapshot* guidance,
                             const map::Projection& projection, const render::MapFrame& frame,
                             const render::LodSelection& selection, const map::TileCache& cache);

    /// The name and ref of the map-matched road of the last annotate() (both empty when there is
    /// none, or no drawn tile has it).
    [[nodiscard]] const render::StreetBar& street() const { return m_frame_street; }

private:
    /// The name and ref of OSM way `way` from the drawn tiles (empty when none has it); cached
    /// while the way and the drawn tiles stay.
    const render::StreetBar& streetOf(std::int64_t way, const render::MapFrame& frame);

    std::int64_t m_way = 0;
    std::size_t m_tiles = 0;
    const map::Tile* m_newest_tile = nullptr;
    render::StreetBar m_street;
    render::StreetBar m_frame_street;
};

/// One lane of the metadata block (ipc::MetaLaneBit) from its arrows (map::lane_arrow bits).
std::uint8_t metaLaneBits(std::uint16_t arrows, bool recommended);

/// The validity alone (FrameAnnotator::annotate's first half), for tests.
ipc::FrameValidity frameValidity(const EstimatedPose& pose, const FrameHealth& health, bool off_route,
                                 std::size_t tiles_missing, std::size_t tiles_failed);

}  // namespace navmap::daemon
