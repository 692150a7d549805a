// SPDX-License-Identifier: Apache-2.0
// The label layout's work grows linearly with the label count: the deterministic counters of
// LayoutStats (pairs handed on by the broad phases, separating-axis tests, grid cells visited)
// summed over the same frames of a scene at N and 2N labels (same density: the synthetic
// screen grows with N) may grow at most 2.3 times. A quadratic loop doubles the factor to 4
// and fails here, on any machine, without timing anything.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "navmap/render/labels/label_layout.h"
#include "synthetic_label_scene.h"

namespace nl = navmap::render::labels;
namespace nt = navmap::test;

namespace {

constexpr double kFrame = 1.0 / 60.0;
constexpr double kLinear = 2.3;  // doubling N: at most this much more work

struct Work {
    std::uint64_t pair_tests = 0;
    std::uint64_t sat_tests = 0;
    std::uint64_t grid_cells = 0;
    std::uint64_t shown = 0;  ///< labels drawn, summed over the frames (the scene is not empty)
};

enum class Motion { Wobble, Churn, Pan };

// Runs a scene for 180 frames and sums the work of the last 120, where placement, forces,
// removals and the drawn-frame overlap rule all run.
Work run(std::size_t n, Motion motion) {
    nt::SyntheticScene scene = nt::makeSyntheticScene(n, 11, motion == Motion::Wobble ? 0.25F : 1.5F);
    nl::LayoutParams p;
    p.max_placements_per_step = static_cast<int>(n / 8);  // placements per step scale with N too
    if (motion == Motion::Wobble) p.placement_zone_px = p.buffer_px;
    nl::LabelLayout layout(p);
    const glm::vec2 view = scene.camera.viewport;
    // Keep-out areas a fixed share of the screen: a marker and the route ahead.
    const std::vector<nl::OrientedBox> keep_out{
        nl::OrientedBox{view * 0.5F, view * 0.04F, {1.0F, 0.0F}},
        nl::OrientedBox{view * glm::vec2(0.5F, 0.3F), view * glm::vec2(0.02F, 0.15F), {0.8F, 0.6F}}};
    layout.setKeepOut(keep_out);
    Work w;
    std::vector<nl::LabelCandidate> present;
    for (int f = 0; f < 180; ++f) {
        switch (motion) {
            case Motion::Wobble: nt::wobbleScene(scene, static_cast<std::uint64_t>(f)); break;
            case Motion::Churn: nt::panScene(scene, {0.5F, -0.5F}); break;
            case Motion::Pan: nt::panScene(scene, {1.0F, 0.5F}); break;  // pixels: the same speed at both sizes
        }
        if (motion == Motion::Churn) {
            // A fifth of the labels leaves the view (culled) for a third of a second, in turn:
            // fading out, coming back, placed again.
            present.clear();
            for (std::size_t i = 0; i < scene.candidates.size(); ++i) {
                if ((i + static_cast<std::size_t>(f / 20)) % 5 != 0) present.push_back(scene.candidates[i]);
            }
            layout.setFrame(present, scene.camera);
        } else {
            layout.setFrame(scene.candidates, scene.camera);
        }
        layout.advance(kFrame);
        if (f < 60) continue;
        const nl::LayoutStats s = layout.stats();
        w.pair_tests += s.last_pair_tests;
        w.sat_tests += s.last_sat_tests;
        w.grid_cells += s.last_grid_cells;
        w.shown += layout.output().size();
    }
    return w;
}

void expectLinear(Motion motion, const char* name) {
    const Work small = run(3000, motion);
    const Work large = run(6000, motion);
    ASSERT_GT(small.shown, 1000U) << name << ": the scene shows labels";
    ASSERT_GT(small.pair_tests, 0U) << name << ": labels meet";
    ASSERT_GT(small.sat_tests, 0U) << name;
    ASSERT_GT(small.grid_cells, 0U) << name;
    const auto ratio = [](std::uint64_t a, std::uint64_t b) { return static_cast<double>(b) / static_cast<double>(a); };
    std::printf("%s: shown %llu -> %llu (x%.2f)\n", name, static_cast<unsigned long long>(small.shown),
                static_cast<unsigned long long>(large.shown), ratio(small.shown, large.shown));
    std::printf("%s: pair tests %llu -> %llu (x%.2f), SAT %llu -> %llu (x%.2f), cells %llu -> %llu (x%.2f)\n", name,
                static_cast<unsigned long long>(small.pair_tests), static_cast<unsigned long long>(large.pair_tests),
                ratio(small.pair_tests, large.pair_tests), static_cast<unsigned long long>(small.sat_tests),
                static_cast<unsigned long long>(large.sat_tests), ratio(small.sat_tests, large.sat_tests),
                static_cast<unsigned long long>(small.grid_cells), static_cast<unsigned long long>(large.grid_cells),
                ratio(small.grid_cells, large.grid_cells));
    EXPECT_LE(ratio(small.pair_tests, large.pair_tests), kLinear) << name << ": pair tests";
    EXPECT_LE(ratio(small.sat_tests, large.sat_tests), kLinear) << name << ": separating-axis tests";
    EXPECT_LE(ratio(small.grid_cells, large.grid_cells), kLinear) << name << ": grid cells";
}

}  // namespace

TEST(LabelLayoutWork, GrowsLinearlyWithEveryLabelPlacedAndMoving) { expectLinear(Motion::Wobble, "wobble"); }

TEST(LabelLayoutWork, GrowsLinearlyInADenseSceneWithLabelsComingAndGoing) { expectLinear(Motion::Churn, "churn"); }

TEST(LabelLayoutWork, GrowsLinearlyInADenseScenePanning) { expectLinear(Motion::Pan, "pan"); }

// The counters are those of the last advance(): a frame without labels counts no work.
TEST(LabelLayoutWork, CountsOnlyTheLastFrame) {
    nt::SyntheticScene scene = nt::makeSyntheticScene(400, 3, 1.0F);
    nl::LabelLayout layout{nl::LayoutParams{}};
    for (int f = 0; f < 30; ++f) {
        layout.setFrame(scene.candidates, scene.camera);
        layout.advance(kFrame);
    }
    EXPECT_GT(layout.stats().last_sat_tests, 0U);
    EXPECT_GT(layout.stats().last_grid_cells, 0U);
    for (int f = 0; f < 60; ++f) {  // every label gone and faded out
        layout.setFrame({}, scene.camera);
        layout.advance(kFrame);
    }
    EXPECT_TRUE(layout.output().empty());
    EXPECT_EQ(layout.stats().last_pair_tests, 0U);
    EXPECT_EQ(layout.stats().last_sat_tests, 0U);
}
