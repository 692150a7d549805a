// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/camera.h"

#include <glm/gtc/matrix_transform.hpp>

namespace navmap::render {

glm::mat4 Camera::viewRelativeTo(const glm::dvec3& origin) const {
    // Subtract in double so far-from-origin scenes keep their precision (docs/architecture.md "Rendering":
    // camera-relative).
    return glm::mat4(glm::lookAt(eye - origin, target - origin, up));
}

glm::mat4 Camera::projection(double aspect) const {
    return glm::mat4(glm::perspective(glm::radians(fov_y_deg), aspect, near_m, far_m));
}

}  // namespace navmap::render
