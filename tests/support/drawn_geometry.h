// SPDX-License-Identifier: Apache-2.0
#pragma once
// Overlap tests on what the renderer reports as drawn (labels::DrawnLabel glyph boxes, the
// marker's outline): convex polygons on screen, separating axis theorem.

#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/render/labels/drawn_label.h"

namespace navmap::test {

/// Penetration depth of two convex polygons (corners in order): the smallest overlap of their
/// projections over every edge normal of both; negative when apart.
float convexOverlapDepth(std::span<const glm::vec2> a, std::span<const glm::vec2> b);

/// Whether any glyph box of `a` overlaps any of `b` by more than `tolerance_px`.
bool glyphsOverlap(std::span<const render::labels::ScreenQuad> a, std::span<const render::labels::ScreenQuad> b,
                   float tolerance_px);

/// Whether any glyph box overlaps the convex `polygon` by more than `tolerance_px` (false when
/// the polygon has fewer than three corners).
bool overlapsPolygon(std::span<const render::labels::ScreenQuad> glyphs, std::span<const glm::vec2> polygon,
                     float tolerance_px);

}  // namespace navmap::test
