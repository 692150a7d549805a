// SPDX-License-Identifier: Apache-2.0
#pragma once
// Deterministic synthetic label scenes for the label layout tests and benchmarks (a fixture of
// navmap_test_fixtures: no installed program links it).

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/render/labels/label_types.h"

namespace navmap::test {

/// A dense synthetic scene: `count` labels (60 % points, 10 % areas, 25 % lines, 5 % circles),
/// text 40..160 x 14..22 px, random priority and depth, uniform anchors in a viewport sized
/// so that the labels' total area is `coverage` times the screen (coverage 1 already leaves
/// many labels without a free spot). Same seed, same scene, on every platform (own PRNG).
struct SyntheticScene {
    std::vector<render::labels::LabelCandidate> candidates;
    render::labels::CameraState camera;
};

[[nodiscard]] SyntheticScene makeSyntheticScene(std::size_t count, std::uint64_t seed, float coverage = 1.5F);

/// Frame `frame` of a wobble: every anchor (and line segment) moves by up to 0.6 px on a
/// Lissajous path of its own phase, so labels collide and forces never rest.
void wobbleScene(SyntheticScene& scene, std::uint64_t frame);

/// Moves every anchor (and line segment) by `delta` pixels: a camera pan.
void panScene(SyntheticScene& scene, glm::vec2 delta);

/// Scales by `scale` and rotates by `angle_rad` about `center` (screen pixels): a camera zoom
/// and turn. Anchors converge when zooming out, which is what makes labels collide.
void zoomRotateScene(SyntheticScene& scene, glm::vec2 center, float scale, float angle_rad);

}  // namespace navmap::test
