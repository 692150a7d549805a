// SPDX-License-Identifier: Apache-2.0
#pragma once
// The Andorra drive the render tests share: the default store built into the build tree
// (Andorra la Vella -> Encamp), opened once per test program, and settled frames along it.

#include <glm/glm.hpp>

#include "drive_scene.h"
#include "navmap/render/camera_rig.h"
#include "navmap/render/map_frame.h"

namespace navmap::test {

/// Opened on first use; later calls return the same scene (tiles stay resident between tests).
DriveScene& andorraDrive();

/// The frame of a camera in `mode` settled `measure_m` along the drive (tiles resident, route
/// and marker set; layers at their defaults) for a width x height view. Flags an incomplete
/// settle as a test failure.
render::MapFrame settledAndorraFrame(render::ViewMode mode, int width, int height, double measure_m = 1800.0,
                                     double speed_mps = 13.0);

/// A constructed case where the drive has none: stands a building in `frame` between the camera and
/// what it shows at pixel `px` of a width x height view. The building is a square block
/// `distance_m` along that line of sight, `cover_px` pixels wide on screen, rising 30 m above the
/// line; the tile under it is copied with the building added. Returns false when no drawn tile
/// lies there.
bool standBuildingInFront(render::MapFrame& frame, glm::vec2 px, float cover_px, int width, int height,
                          double distance_m = 120.0);

}  // namespace navmap::test
