// SPDX-License-Identifier: Apache-2.0
// DrawnLabelMetrics: every definition of docs/labels.md "Measured quality" on synthetic drawn
// frames, with the edges of each rule (1 px tolerance, opacity 0.5, 10 % hidden, 9 px cap
// height, 64 px interior margin, texts shared by two ids).
#include <vector>

#include <gtest/gtest.h>

#include "drawn_label_metrics.h"

namespace nl = navmap::render::labels;

namespace {

const glm::vec2 kViewport{1280.0F, 480.0F};
constexpr double kDt = 0.5;

nl::ScreenQuad rect(glm::vec2 lo, glm::vec2 hi) { return {lo, glm::vec2(hi.x, lo.y), hi, glm::vec2(lo.x, hi.y)}; }

// A label with one glyph box [lo, hi], anchored at the box's center.
nl::DrawnLabel label(std::uint64_t id, glm::vec2 lo, glm::vec2 hi, float opacity = 1.0F) {
    nl::DrawnLabel l;
    l.id = id;
    l.text = "label " + std::to_string(id);
    l.opacity = opacity;
    l.center = 0.5F * (lo + hi);
    l.anchor = l.center;
    l.cap_height_px = 12.0F;
    l.glyph_boxes.push_back(rect(lo, hi));
    return l;
}

// A point label at `anchor` (a 20 x 10 px box just above it).
nl::DrawnLabel pointAt(std::uint64_t id, glm::vec2 anchor, float opacity = 1.0F,
                       nl::LabelKind kind = nl::LabelKind::Point) {
    nl::DrawnLabel l = label(id, anchor - glm::vec2(10, 12), anchor + glm::vec2(10, -2), opacity);
    l.anchor = anchor;
    l.kind = kind;
    return l;
}

nl::DrawnFrameFigures add(nl::DrawnLabelMetrics& m, const std::vector<nl::DrawnLabel>& labels,
                          const nl::DrawnMarker& marker = {}) {
    return m.addFrame(labels, marker, kViewport, kDt);
}

}  // namespace

TEST(DrawnLabelMetrics, PenetrationDepthOfConvexPolygons) {
    const nl::ScreenQuad a = rect({0, 0}, {10, 10});
    EXPECT_FLOAT_EQ(nl::DrawnLabelMetrics::penetrationDepth(a, rect({7, 2}, {20, 8})), 3.0F);
    EXPECT_FLOAT_EQ(nl::DrawnLabelMetrics::penetrationDepth(a, rect({10, 0}, {20, 10})), 0.0F);   // touching
    EXPECT_FLOAT_EQ(nl::DrawnLabelMetrics::penetrationDepth(a, rect({12, 0}, {20, 10})), -2.0F);  // 2 px apart
    // A diamond whose bounding box overlaps the square's corner by 2 px on both axes, but whose
    // edge separates it: only the SAT over the diamond's own edge normals sees that.
    const nl::ScreenQuad diamond{glm::vec2(13, 8), glm::vec2(18, 13), glm::vec2(13, 18), glm::vec2(8, 13)};
    EXPECT_LT(nl::DrawnLabelMetrics::penetrationDepth(a, diamond), 0.0F);
    // Degenerate input never overlaps.
    const std::vector<glm::vec2> line{{0, 0}, {10, 10}};
    EXPECT_LT(nl::DrawnLabelMetrics::penetrationDepth(a, line), -1e30F);
    const nl::ScreenQuad point{glm::vec2(5, 5), glm::vec2(5, 5), glm::vec2(5, 5), glm::vec2(5, 5)};
    EXPECT_LT(nl::DrawnLabelMetrics::penetrationDepth(point, point), -1e30F);
}

TEST(DrawnLabelMetrics, VisibleIsOpacityAtLeastHalfCountedOncePerIdWithMedianMeanMin) {
    nl::DrawnLabelMetrics m;
    // Frame 1: opacity 0.5 counts, 0.49 does not; id 3 drawn twice (one label, one duplicate).
    EXPECT_EQ(add(m, {label(1, {0, 0}, {10, 10}, 0.5F), label(2, {100, 0}, {110, 10}, 0.49F),
                      label(3, {200, 0}, {210, 10}), label(3, {300, 0}, {310, 10}, 0.2F)})
                  .visible,
              2U);
    EXPECT_EQ(add(m, {}).visible, 0U);
    add(m, {label(1, {0, 0}, {10, 10}), label(2, {100, 0}, {110, 10}), label(3, {200, 0}, {210, 10}),
            label(4, {300, 0}, {310, 10})});
    add(m, {label(1, {0, 0}, {10, 10}), label(2, {100, 0}, {110, 10}), label(3, {200, 0}, {210, 10})});
    nl::DrawnLabelQuality q = m.summary();
    EXPECT_EQ(q.frames, 4U);
    EXPECT_DOUBLE_EQ(q.seconds, 2.0);
    EXPECT_DOUBLE_EQ(q.visible_median, 2.5);  // counts 0 2 3 4: even count, mean of the middle two
    EXPECT_DOUBLE_EQ(q.visible_mean, 9.0 / 4.0);
    EXPECT_EQ(q.visible_min, 0U);
    EXPECT_EQ(q.visible_max, 4U);
    EXPECT_EQ(q.visible_label_frames, 9U);
    EXPECT_EQ(q.distinct_visible_labels, 4U);
    EXPECT_EQ(q.duplicate_ids, 1U);
    add(m, {label(7, {0, 0}, {10, 10})});
    EXPECT_DOUBLE_EQ(m.summary().visible_median, 2.0);  // 0 1 2 3 4
}

TEST(DrawnLabelMetrics, OverlapsNeedMoreThanOnePixelOfGlyphPenetration) {
    nl::DrawnLabelMetrics m;
    // 1 and 2 overlap by exactly 1 px: not counted. 3 and 4 by 1.5 px: counted. 5 overlaps 6 by
    // 4 px but 6 is not visible. 7's own glyphs overlap each other: not a pair.
    nl::DrawnLabel seven = label(7, {600, 0}, {620, 10});
    seven.glyph_boxes.push_back(rect({610, 0}, {630, 10}));
    const nl::DrawnFrameFigures f = add(m, {label(1, {0, 0}, {10, 10}), label(2, {9, 0}, {19, 10}),
                                            label(3, {100, 0}, {110, 10}), label(4, {108.5F, 2}, {120, 8}),
                                            label(5, {200, 0}, {210, 10}), label(6, {206, 0}, {216, 10}, 0.3F), seven});
    EXPECT_EQ(f.overlap_pairs, 1U);
    // Bounding boxes of whole labels overlap, glyphs do not (a gap between two glyphs of 8).
    nl::DrawnLabel eight = label(8, {0, 0}, {10, 10});
    eight.glyph_boxes.push_back(rect({30, 0}, {40, 10}));
    EXPECT_EQ(add(m, {eight, label(9, {12, 0}, {28, 10})}).overlap_pairs, 0U);
    // Three labels on one spot: three pairs.
    EXPECT_EQ(
        add(m, {label(1, {0, 0}, {10, 10}), label(2, {2, 0}, {12, 10}), label(3, {4, 0}, {14, 10})}).overlap_pairs, 3U);
    const nl::DrawnLabelQuality q = m.summary();
    EXPECT_EQ(q.overlap_pairs_max, 3U);
    EXPECT_EQ(q.overlap_pairs_sum, 4U);
    EXPECT_EQ(q.overlap_frames, 2U);
}

TEST(DrawnLabelMetrics, OccludedShareCountsMeasuredLabelsAndReportsUnmeasuredApart) {
    nl::DrawnLabelMetrics m;
    auto occluded = [](std::uint64_t id, float fraction, float opacity = 1.0F) {
        nl::DrawnLabel l = label(id, {id * 50.0F, 0}, {id * 50.0F + 10, 10}, opacity);
        l.occluded_fraction = fraction;
        return l;
    };
    add(m, {occluded(1, 0.10F), occluded(2, 0.11F), occluded(3, -1.0F), occluded(4, 0.0F), occluded(5, 0.9F, 0.4F)});
    add(m, {occluded(1, 0.5F), occluded(3, -1.0F)});
    const nl::DrawnLabelQuality q = m.summary();
    EXPECT_EQ(q.occlusion_measured_label_frames, 4U);  // 1, 2, 4; then 1 (5 is not visible)
    EXPECT_EQ(q.occlusion_unmeasured_label_frames, 2U);
    EXPECT_EQ(q.occluded_label_frames, 2U);  // 2 (0.11), then 1 (0.5); 0.10 is not more than 10 %
    EXPECT_DOUBLE_EQ(q.occluded_share, 0.5);
}

TEST(DrawnLabelMetrics, TooSmallIsCapHeightUnderNinePixels) {
    nl::DrawnLabelMetrics m;
    auto sized = [](std::uint64_t id, float cap, float opacity = 1.0F) {
        nl::DrawnLabel l = label(id, {id * 50.0F, 0}, {id * 50.0F + 10, 10}, opacity);
        l.cap_height_px = cap;
        return l;
    };
    add(m, {sized(1, 8.9F), sized(2, 9.0F), sized(3, 4.0F, 0.2F)});
    add(m, {sized(1, 8.0F), sized(2, 8.5F)});
    add(m, {sized(1, 8.0F)});
    const nl::DrawnLabelQuality q = m.summary();
    EXPECT_EQ(q.too_small_label_frames, 4U);
    EXPECT_EQ(q.too_small_labels, 2U);
    EXPECT_DOUBLE_EQ(q.too_small_share, 4.0 / 5.0);
}

TEST(DrawnLabelMetrics, MarkerOverlapIsGlyphOverMarkerOutlineByMoreThanOnePixel) {
    nl::DrawnLabelMetrics m;
    nl::DrawnMarker marker;
    marker.outline = {{100, 100}, {120, 140}, {80, 140}};  // a triangle, tip up, base at y 140
    // 1: 2 px into the base. 2: 0.5 px into it. 3: 5 px in but fading (0.3). 4: inside the
    // triangle's bounding box beside its slanted edge, clear of it.
    const nl::DrawnFrameFigures f = add(m,
                                        {label(1, {95, 138}, {105, 150}), label(2, {96, 139.5F}, {104, 150}),
                                         label(3, {90, 135}, {110, 150}, 0.3F), label(4, {80, 100}, {88, 108})},
                                        marker);
    EXPECT_EQ(f.marker_overlaps, 1U);
    add(m, {label(1, {95, 138}, {105, 150})});  // no marker drawn in this frame
    add(m, {label(1, {95, 138}, {105, 150}), label(2, {95, 130}, {105, 135})}, marker);
    const nl::DrawnLabelQuality q = m.summary();
    EXPECT_EQ(q.marker_frames, 2U);
    EXPECT_EQ(q.marker_overlap_label_frames, 3U);
    EXPECT_EQ(q.marker_overlap_frames, 2U);
    EXPECT_EQ(q.marker_overlap_labels, 2U);
}

TEST(DrawnLabelMetrics, AFadeInPopsOnceWhenItCrossesHalfOpacity) {
    nl::DrawnLabelMetrics m;
    std::size_t pops = 0;
    for (int i = 0; i <= 10; ++i) {
        // Label 1 fades in from 0 to 1 (crossing 0.5 at i = 5); label 2 stays.
        const auto f = add(m, {pointAt(1, {600, 200}, 0.1F * static_cast<float>(i)), pointAt(2, {300, 200})});
        pops += f.pops;
        EXPECT_EQ(f.pops, i == 5 ? 1U : 0U) << "frame " << i;
    }
    EXPECT_EQ(pops, 1U);
    // Hovering around 0.5 crosses it every frame: each crossing is a pop.
    add(m, {pointAt(1, {600, 200}, 0.49F), pointAt(2, {300, 200})});
    add(m, {pointAt(1, {600, 200}, 0.51F), pointAt(2, {300, 200})});
    // Leaving the frame altogether counts like fading out.
    add(m, {pointAt(2, {300, 200})});
    const nl::DrawnLabelQuality q = m.summary();
    EXPECT_EQ(q.frames, 14U);
    EXPECT_EQ(q.pops, 4U);
    EXPECT_DOUBLE_EQ(q.pops_per_s, 4.0 / 7.0);
    EXPECT_EQ(q.frames_with_pop, 4U);
    EXPECT_DOUBLE_EQ(q.pop_frame_share, 4.0 / 13.0);
}

TEST(DrawnLabelMetrics, FirstFrameIsNoPop) {
    nl::DrawnLabelMetrics m;
    EXPECT_EQ(add(m, {pointAt(1, {600, 200}), pointAt(2, {300, 200})}).pops, 0U);
    EXPECT_EQ(m.summary().pops, 0U);
    EXPECT_EQ(m.summary().text_pops, 0U);
    EXPECT_DOUBLE_EQ(m.summary().pop_frame_share, 0.0);
}

TEST(DrawnLabelMetrics, InteriorPointPopsNeedTheAnchor64PixelsInsideWhereTheLabelIsVisible) {
    nl::DrawnLabelMetrics m;
    add(m, {});
    // Entering: the anchor of the frame in which the label is visible counts.
    auto f = add(m, {pointAt(1, {64, 64}), pointAt(2, {63, 200}), pointAt(3, {1216, 416}), pointAt(4, {1217, 200}),
                     pointAt(5, {600, 200}, 1.0F, nl::LabelKind::Area),
                     pointAt(6, {600, 300}, 1.0F, nl::LabelKind::Line), pointAt(7, {600, 416.5F})});
    EXPECT_EQ(f.pops, 7U);
    EXPECT_EQ(f.interior_point_pops, 3U);  // 1, 3 (exactly 64 px in) and 5 (an area)
    // Leaving: the anchor of the last frame in which it was visible counts, not where its fading
    // remains are drawn now. 1 fades while its anchor reaches the edge: an interior pop. 2 walks
    // in from the edge and fades there: not interior where it was visible.
    f = add(m, {pointAt(1, {10, 10}, 0.3F), pointAt(2, {600, 200}, 0.3F), pointAt(3, {1216, 416}),
                pointAt(4, {1217, 200}), pointAt(5, {600, 200}, 1.0F, nl::LabelKind::Area),
                pointAt(6, {600, 300}, 1.0F, nl::LabelKind::Line), pointAt(7, {600, 416.5F})});
    EXPECT_EQ(f.pops, 2U);
    EXPECT_EQ(f.interior_point_pops, 1U);
    const nl::DrawnLabelQuality q = m.summary();
    EXPECT_EQ(q.pops, 9U);
    EXPECT_EQ(q.interior_point_pops, 4U);
    EXPECT_DOUBLE_EQ(q.interior_point_pops_per_s, 4.0 / 1.5);
}

TEST(DrawnLabelMetrics, TextPopsCountTextsNotIds) {
    nl::DrawnLabelMetrics m;
    auto named = [](std::uint64_t id, const char* text, glm::vec2 at, float opacity = 1.0F) {
        nl::DrawnLabel l = pointAt(id, at, opacity, nl::LabelKind::Line);
        l.text = text;
        return l;
    };
    add(m, {named(1, "Avinguda Meritxell", {300, 200}), named(3, "Carrer Major", {600, 200})});
    // The street's name moves from piece 1 to piece 2 of the same street: two id pops, no text pop.
    auto f = add(m, {named(2, "Avinguda Meritxell", {400, 200}), named(3, "Carrer Major", {600, 200})});
    EXPECT_EQ(f.pops, 2U);
    EXPECT_EQ(f.text_pops, 0U);
    // Two pieces share the name; one goes: no text pop. Then the last goes: one text pop.
    add(m, {named(2, "Avinguda Meritxell", {400, 200}), named(4, "Avinguda Meritxell", {800, 200}),
            named(3, "Carrer Major", {600, 200})});
    f = add(m, {named(4, "Avinguda Meritxell", {800, 200}), named(3, "Carrer Major", {600, 200})});
    EXPECT_EQ(f.pops, 1U);
    EXPECT_EQ(f.text_pops, 0U);
    f = add(m, {named(3, "Carrer Major", {600, 200}), named(4, "Avinguda Meritxell", {800, 200}, 0.2F)});
    EXPECT_EQ(f.pops, 1U);
    EXPECT_EQ(f.text_pops, 1U);
    const nl::DrawnLabelQuality q = m.summary();
    EXPECT_EQ(q.pops, 5U);
    EXPECT_EQ(q.text_pops, 1U);
    EXPECT_DOUBLE_EQ(q.text_pops_per_s, 1.0 / 2.5);
}

TEST(DrawnLabelMetrics, JitterIsMotionRelativeToTheAnchorOfVisibleLabels) {
    nl::DrawnLabelMetrics m;
    auto at = [](std::uint64_t id, glm::vec2 center, glm::vec2 anchor, float opacity = 1.0F) {
        nl::DrawnLabel l = label(id, center - glm::vec2(5), center + glm::vec2(5), opacity);
        l.anchor = anchor;
        return l;
    };
    add(m, {at(1, {100, 100}, {100, 110}), at(2, {300, 100}, {300, 110}), at(3, {500, 100}, {500, 110}, 0.2F)});
    // 1 moves 3-4-5 px against a fixed anchor; 2 moves with its anchor (camera motion): 0;
    // 3 is not visible in either frame.
    add(m, {at(1, {103, 104}, {100, 110}), at(2, {350, 130}, {350, 140}), at(3, {530, 100}, {500, 110}, 0.3F)});
    // 1 jumps 40 px: jitter too (a jump is not a pop by the placement's count).
    add(m, {at(1, {143, 104}, {100, 110}), at(2, {350, 130}, {350, 140})});
    const nl::DrawnLabelQuality q = m.summary();
    EXPECT_EQ(q.jitter_samples, 4U);
    EXPECT_DOUBLE_EQ(q.jitter_mean_px, 45.0 / 4.0);
    EXPECT_DOUBLE_EQ(q.jitter_p95_px, 40.0);  // nearest rank: ceil(0.95 * 4) = 4th of 0 0 5 40
    EXPECT_DOUBLE_EQ(q.jitter_max_px, 40.0);
    EXPECT_EQ(q.pops, 0U);
}

TEST(DrawnLabelMetrics, ResetStartsOver) {
    nl::DrawnLabelMetrics m;
    add(m, {pointAt(1, {600, 200})});
    add(m, {});
    ASSERT_EQ(m.summary().pops, 1U);
    m.reset();
    EXPECT_EQ(add(m, {}).pops, 0U);  // a first frame again: nothing to compare with
    const nl::DrawnLabelQuality q = m.summary();
    EXPECT_EQ(q.frames, 1U);
    EXPECT_EQ(q.pops, 0U);
    EXPECT_EQ(q.distinct_visible_labels, 0U);
}
