// SPDX-License-Identifier: Apache-2.0
#pragma once
// CIE L*a*b* (D65) of sRGB colours and the CIE76 colour difference, the measure of the
// orthoimage network against Blue Marble (docs/orthoimage.md "Quality").

#include <array>

namespace navmap::map::ortho {

/// sRGB components in [0, 1] -> L*, a*, b*.
std::array<double, 3> srgbToLab(const std::array<float, 3>& rgb);
/// Euclidean distance in L*a*b* of two sRGB colours (components clamped to [0, 1]).
double deltaE76(const std::array<float, 3>& a, const std::array<float, 3>& b);

}  // namespace navmap::map::ortho
