// SPDX-License-Identifier: Apache-2.0
#pragma once
// What one map frame gives every pass of MapRenderer: the frame, the display target it draws
// into, the camera's projection, the style, the tiles drawn (nearest first, from GpuTileCache)
// and the frame's statistics. Built once per frame by MapRenderer::beginFrame; the passes read
// it and write only the statistics of their own pass. Private to render/.

#include <array>
#include <chrono>
#include <span>

#include <glm/glm.hpp>

#include "navmap/render/map_frame.h"
#include "navmap/render/road_style.h"
#include "render_target.h"

namespace navmap::render::gl {

struct GpuTile;

using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

struct FrameContext {
    const MapFrame& frame;
    const RenderTarget& target;  ///< the display's offscreen target
    int target_id = 0;           ///< which display (GpuTileCache and the label state are per display)
    const MapStyle& style;
    glm::mat4 projection{1.0f};  ///< the frame camera's, for the target's aspect
    glm::vec2 viewport{0.0f};    ///< the target's size, pixels
    double frame_dt_s = 0.0;     ///< time since the display's previous frame (MapFrame::frame_dt_s)
    /// This frame's tiles, nearest first, with their view matrices set (GpuTile::view).
    std::span<GpuTile* const> tiles;
    /// This frame's selection of road classes (seed 7.3).
    std::array<SelectionFade, kStyledRoadClasses> selection{};
    bool whole_caps = false;  ///< !MapLayers::trim_joint_caps
    MapFrameStats& stats;

    [[nodiscard]] const MapLayers& layers() const { return frame.layers; }
    [[nodiscard]] bool routeShown() const { return frame.layers.route && frame.route; }
};

}  // namespace navmap::render::gl
