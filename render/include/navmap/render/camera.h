// SPDX-License-Identifier: Apache-2.0
#pragma once
// Perspective camera in the map's planar frame (metres east, north, up; see map/projection.h).

#include <glm/glm.hpp>

namespace navmap::render {

/// A perspective camera. Positions are double precision in the map frame; the renderer
/// subtracts the geometry's origin in double before going to float (camera-relative rendering).
struct Camera {
    glm::dvec3 eye{0.0, -1000.0, 1000.0};  ///< metres
    glm::dvec3 target{0.0, 0.0, 0.0};      ///< metres
    glm::dvec3 up{0.0, 0.0, 1.0};
    double fov_y_deg = 45.0;  ///< vertical field of view
    double near_m = 10.0;
    double far_m = 60000.0;

    /// View matrix for geometry whose coordinates are relative to `origin`.
    [[nodiscard]] glm::mat4 viewRelativeTo(const glm::dvec3& origin) const;
    /// OpenGL-style projection for the given aspect ratio (width / height).
    [[nodiscard]] glm::mat4 projection(double aspect) const;
};

}  // namespace navmap::render
