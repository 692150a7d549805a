// SPDX-License-Identifier: Apache-2.0
#include <vector>

#include <gtest/gtest.h>

#include "layout_metrics.h"

namespace nl = navmap::render::labels;

namespace {

nl::PlacedLabel label(std::uint64_t id, glm::vec2 center, float alpha = 1.0F,
                      nl::LabelState state = nl::LabelState::Visible, glm::vec2 anchor = {0, 0}) {
    nl::PlacedLabel l;
    l.id = id;
    l.state = state;
    l.box = {center, {50, 10}, {1, 0}};
    l.anchor = anchor;
    l.alpha = alpha;
    return l;
}

}  // namespace

TEST(LayoutMetrics, CountsOverlapsAmongVisibleLabelsOnly) {
    const std::vector labels = {
        label(1, {0, 0}),
        label(2, {90, 5}),  // overlap
        label(3, {300, 0}),
        label(4, {400, 0}),                                   // touching: no overlap
        label(5, {300, 5}, 0.5F, nl::LabelState::FadingOut),  // fading out: not counted
        label(6, {600, 0}),
        label(7, {610, 0}, 0.1F, nl::LabelState::FadingIn),  // fading in counts
    };
    EXPECT_EQ(nl::LayoutMetrics::countOverlaps(labels), 2U);
}

TEST(LayoutMetrics, PopsJitterAndVisibleCounts) {
    nl::LayoutMetrics m;
    const double dt = 0.5;
    m.addFrame(std::vector{label(1, {10, 0}), label(2, {300, 0}, 0.1F, nl::LabelState::FadingIn)}, dt);
    // Label 1 moves by 3 px with a fixed anchor: jitter 3. Its anchor also moves in the next
    // frame, together with the label: no jitter. Label 3 pops in at full alpha; label 2
    // fades in normally.
    m.addFrame(std::vector{label(1, {13, 4}), label(2, {300, 0}, 0.3F, nl::LabelState::FadingIn), label(3, {600, 0})},
               dt);
    m.addFrame(std::vector{label(1, {113, 4}, 1.0F, nl::LabelState::Visible, {100, 0}),
                           label(2, {300, 0}, 0.5F, nl::LabelState::FadingIn), label(3, {600, 0})},
               dt);
    // Label 3 vanishes at full alpha: a pop. Label 1 jumps by 40 px: a pop too.
    m.addFrame(std::vector{label(1, {153, 4}, 1.0F, nl::LabelState::Visible, {100, 0}),
                           label(2, {300, 0}, 0.7F, nl::LabelState::FadingIn)},
               dt);
    const nl::LayoutQuality q = m.summary();
    EXPECT_EQ(q.frames, 4U);
    EXPECT_DOUBLE_EQ(q.seconds, 2.0);
    EXPECT_EQ(q.pops, 3U);
    EXPECT_DOUBLE_EQ(q.pops_per_s, 1.5);
    EXPECT_DOUBLE_EQ(q.mean_visible, 10.0 / 4.0);
    EXPECT_EQ(q.last_visible, 2U);
    // Jitter samples: label 1 (5 px: 3-4-5 triangle, then 0 px), label 2 (0, 0, 0), label 3
    // (0). The 40 px jump is a pop, not jitter.
    EXPECT_EQ(q.jitter_samples, 6U);
    EXPECT_NEAR(q.mean_jitter_px, 5.0 / 6.0, 1e-6);
    EXPECT_NEAR(q.p95_jitter_px, 5.0, 0.051);
    EXPECT_EQ(q.max_overlaps, 0U);
    m.reset();
    EXPECT_EQ(m.summary().frames, 0U);
}
