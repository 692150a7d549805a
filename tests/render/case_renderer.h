// SPDX-License-Identifier: Apache-2.0
#pragma once
// Renders a render case (render_case.h): a settled frame of the Andorra drive with the case's
// view, layers, style and guidance, or a heightfield, on a renderer of its own.

#include <string>
#include <vector>

#include "navmap/render/image.h"
#include "navmap/render/map_frame.h"
#include "render_case.h"

namespace navmap::test {

/// The last frame a case rendered, what its renderer drew it with and the features its context
/// turned off (DeviceInfo::features_off).
struct CaseFrame {
    render::Image image;
    render::MapFrameStats stats;
    std::vector<std::string> features_off;
};

/// Renders `c`. A drive whose tiles do not all load in time is a test failure (settledAndorraFrame).
CaseFrame renderCase(const RenderCase& c);

}  // namespace navmap::test
