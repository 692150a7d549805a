// SPDX-License-Identifier: Apache-2.0
#pragma once
// The display profiles of docs/architecture.md "Display profiles" as the frame benchmarks render them.

#include "navmap/render/camera_rig.h"

namespace navmap::bench {

struct DisplayProfile {
    const char* name;
    int width, height;
    render::ViewMode mode;
};

inline constexpr DisplayProfile kCluster{"cluster", 1280, 480, render::ViewMode::Snail};
inline constexpr DisplayProfile kHud{"hud", 800, 240, render::ViewMode::Snail};
inline constexpr DisplayProfile kCenter{"center", 1280, 720, render::ViewMode::Bird};

}  // namespace navmap::bench
