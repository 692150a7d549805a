// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "layout_metrics.h"
#include "navmap/render/labels/label_layout.h"
#include "synthetic_label_scene.h"

namespace nl = navmap::render::labels;
namespace nt = navmap::test;

namespace {

constexpr double kFrame = 1.0 / 60.0;

nl::LabelCandidate point(std::uint64_t id, glm::vec2 anchor, float priority = 0.5F, glm::vec2 size = {100, 20}) {
    nl::LabelCandidate c;
    c.id = id;
    c.anchor = anchor;
    c.priority = priority;
    c.size = size;
    return c;
}

nl::CameraState camera(float tilt = 30.0F) {
    nl::CameraState cam;
    cam.tilt_deg = tilt;
    cam.viewport = {1280, 720};
    return cam;
}

// Feeds the same candidates for `seconds` at 60 fps.
void run(nl::LabelLayout& layout, const std::vector<nl::LabelCandidate>& c, double seconds,
         const nl::CameraState& cam = camera()) {
    const int frames = static_cast<int>(std::lround(seconds / kFrame));
    for (int f = 0; f < frames; ++f) {
        layout.setFrame(c, cam);
        layout.advance(kFrame);
    }
}

const nl::PlacedLabel* find(const nl::LabelLayout& layout, std::uint64_t id) {
    for (const auto& l : layout.output()) {
        if (l.id == id) return &l;
    }
    return nullptr;
}

bool sameOutput(std::span<const nl::PlacedLabel> a, std::span<const nl::PlacedLabel> b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const auto& x = a[i];
        const auto& y = b[i];
        // Bitwise: the layout is deterministic to the bit, not only within a tolerance.
        // NOLINTBEGIN(bugprone-suspicious-memory-comparison)
        if (x.id != y.id || x.state != y.state || x.candidate != y.candidate ||
            std::memcmp(&x.box, &y.box, sizeof x.box) != 0 || std::memcmp(&x.alpha, &y.alpha, sizeof x.alpha) != 0 ||
            std::memcmp(&x.scale, &y.scale, sizeof x.scale) != 0) {
            return false;
        }
        // NOLINTEND(bugprone-suspicious-memory-comparison)
    }
    return true;
}

}  // namespace

TEST(LabelLayout, InvalidParamsThrowNamingTheField) {
    nl::LayoutParams p;
    p.placement_zone_px = 1.0F;  // below buffer_px
    try {
        nl::LabelLayout layout(p);
        FAIL() << "expected LabelLayoutError";
    } catch (const nl::LabelLayoutError& e) {
        EXPECT_NE(std::string(e.what()).find("placement_zone_px"), std::string::npos) << e.what();
    }
    p = {};
    p.step_s = 0.0;
    EXPECT_THROW(nl::LabelLayout{p}, nl::LabelLayoutError);
    p = {};
    p.placement_lookahead_s = -1.0F;
    EXPECT_THROW(nl::LabelLayout{p}, nl::LabelLayoutError);
    p = {};
    p.established_s = std::nanf("");
    EXPECT_THROW(nl::LabelLayout{p}, nl::LabelLayoutError);
}

TEST(LabelLayout, BadCandidatesAreRejectedWithAMessage) {
    nl::LabelLayout layout;
    std::vector<nl::LabelCandidate> c = {point(1, {100, 100}), point(42, {NAN, 3}), point(7, {300, 300}),
                                         point(7, {500, 500}), point(9, {200, 200}, 0.5F, {0, 10})};
    const nl::FrameReport r = layout.setFrame(c, camera());
    EXPECT_EQ(r.accepted, 2U);
    EXPECT_EQ(r.rejected, 3U);
    EXPECT_NE(r.first_error.find("label id 42"), std::string::npos) << r.first_error;
    EXPECT_NE(r.first_error.find("anchor"), std::string::npos) << r.first_error;
    layout.advance(kFrame);
    ASSERT_EQ(layout.output().size(), 2U);
    EXPECT_EQ(layout.output()[0].id, 1U);
    EXPECT_EQ(layout.output()[1].id, 7U);
    EXPECT_EQ(layout.output()[1].anchor, glm::vec2(300, 300));  // first of the duplicates wins
    EXPECT_EQ(layout.stats().rejected_inputs, 3U);
    // Time that is not a time runs nothing.
    EXPECT_EQ(layout.advance(-1.0), 0);
    EXPECT_EQ(layout.advance(NAN), 0);
}

TEST(LabelLayout, FourPositionModelPrefersUpperRight) {
    nl::LabelLayout layout;
    run(layout, {point(1, {400, 300})}, 0.1);
    const auto* l = find(layout, 1);
    ASSERT_NE(l, nullptr);
    EXPECT_EQ(l->candidate, 0);
    EXPECT_NEAR(l->box.center.x, 400 + 50 + 4, 1e-3F);  // right of the anchor by half width + gap
    EXPECT_NEAR(l->box.center.y, 300 - 10 - 4, 1e-3F);  // above it
    // At the right screen edge the upper-left candidate is taken instead.
    nl::LabelLayout edge;
    run(edge, {point(2, {1250, 300})}, 0.1);
    ASSERT_NE(find(edge, 2), nullptr);
    EXPECT_EQ(find(edge, 2)->candidate, 1);
    EXPECT_LT(find(edge, 2)->box.center.x, 1250.0F);
}

TEST(LabelLayout, FadesInThenOutWhenGone) {
    nl::LabelLayout layout;  // fade_in_s = fade_out_s = 0.4
    layout.setFrame(std::vector{point(1, {400, 300})}, camera());
    layout.advance(kFrame);
    ASSERT_NE(find(layout, 1), nullptr);
    EXPECT_EQ(find(layout, 1)->state, nl::LabelState::FadingIn);
    const float a1 = find(layout, 1)->alpha;
    EXPECT_GT(a1, 0.0F);
    EXPECT_LT(a1, 0.1F);
    run(layout, {point(1, {400, 300})}, 0.2);
    EXPECT_NEAR(find(layout, 1)->alpha, a1 + 12.0F / 24.0F, 1e-3F);
    run(layout, {point(1, {400, 300})}, 0.3);
    EXPECT_EQ(find(layout, 1)->state, nl::LabelState::Visible);
    EXPECT_EQ(find(layout, 1)->alpha, 1.0F);

    run(layout, {}, 0.2);  // gone from the input: fades out where it was
    ASSERT_NE(find(layout, 1), nullptr);
    EXPECT_EQ(find(layout, 1)->state, nl::LabelState::FadingOut);
    EXPECT_NEAR(find(layout, 1)->alpha, 0.5F, 1e-3F);
    EXPECT_EQ(find(layout, 1)->anchor, glm::vec2(400, 300));
    run(layout, {}, 0.25);
    EXPECT_EQ(find(layout, 1), nullptr);
}

TEST(LabelLayout, PriorityOrderAndPlacementBudget) {
    nl::LayoutParams p;
    p.max_placements_per_step = 2;
    nl::LabelLayout layout(p);
    std::vector<nl::LabelCandidate> c;
    c.reserve(10);
    for (int i = 0; i < 10; ++i) {
        c.push_back(point(static_cast<std::uint64_t>(i + 1),
                          {100.0F + 130.0F * static_cast<float>(i % 5), 100.0F + 200.0F * static_cast<float>(i / 5)},
                          0.1F * static_cast<float>(i)));
    }
    layout.setFrame(c, camera());
    layout.step();
    layout.updateOutput();
    ASSERT_EQ(layout.output().size(), 2U);  // bounded per step
    EXPECT_EQ(layout.output()[0].id, 9U);   // the two most important first
    EXPECT_EQ(layout.output()[1].id, 10U);
    for (int s = 0; s < 4; ++s) layout.step();
    layout.updateOutput();
    EXPECT_EQ(layout.output().size(), 10U);

    // Two labels on one anchor: only the more important one gets it.
    nl::LabelLayout same;
    run(same, {point(5, {400, 300}, 0.2F), point(6, {400, 300}, 0.9F)}, 0.1);
    ASSERT_EQ(same.output().size(), 1U);
    EXPECT_EQ(same.output()[0].id, 6U);
    EXPECT_EQ(same.stats().waiting, 1U);
}

TEST(LabelLayout, BlockedLabelRetriesAfterItsTimer) {
    nl::LabelLayout layout;  // retry_delay_s = 1 (staggered up to 1.25)
    const auto a = point(1, {400, 300}, 0.9F);
    const auto b = point(2, {400, 300}, 0.1F);
    run(layout, {a, b}, 0.1);
    EXPECT_EQ(find(layout, 2), nullptr);
    run(layout, {b}, 0.5);  // the blocker is gone, but b waits for its timer
    EXPECT_EQ(find(layout, 2), nullptr);
    run(layout, {b}, 0.8);  // 1.4 s after the failed attempt
    ASSERT_NE(find(layout, 2), nullptr);
    EXPECT_EQ(find(layout, 2)->candidate, 0);
}

TEST(LabelLayout, TwoConvergingLabelsArePushedApart) {
    nl::LabelLayout layout;
    // Placed apart first, then the camera moves label 2's anchor towards label 1 over a second:
    // the buffered boxes touch first and the collision force (seed 4.4.4) pushes them apart
    // before their text boxes overlap.
    run(layout, {point(1, {400, 300}), point(2, {400, 500})}, 0.6);
    ASSERT_EQ(layout.output().size(), 2U);
    for (int f = 0; f <= 60; ++f) {
        const float y = 500.0F - 190.0F * static_cast<float>(f) / 60.0F;
        layout.setFrame(std::vector{point(1, {400, 300}), point(2, {400, y})}, camera());
        layout.advance(kFrame);
        ASSERT_EQ(nl::LayoutMetrics::countOverlaps(layout.output()), 0U) << "frame " << f;
    }
    // The collision force pushed the upper one up from its rest while they converged ...
    ASSERT_NE(find(layout, 1), nullptr);
    EXPECT_LT(find(layout, 1)->box.center.y, 300.0F - 14.0F - 0.3F);
    // ... and held there, pressed together by their springs, the less important one (same
    // priority, higher id) fades out after overlap_removal_s instead of staying squeezed.
    run(layout, {point(1, {400, 300}), point(2, {400, 310})}, 2.0);
    EXPECT_EQ(find(layout, 1)->state, nl::LabelState::Visible);
    EXPECT_EQ(layout.stats().removed_overlap, 1U);
    EXPECT_EQ(nl::LayoutMetrics::countOverlaps(layout.output()), 0U);
}

TEST(LabelLayout, OverlappingTextIsNeverDrawnVisible) {
    // The camera jumps: two text boxes land on each other in one frame. In that very frame the
    // less important label drops below the visible opacity and fades out; it comes back later
    // where there is room.
    nl::LabelLayout layout;
    run(layout, {point(1, {400, 300}, 0.3F), point(2, {400, 500}, 0.8F)}, 0.6);
    const std::vector moved = {point(1, {400, 300}, 0.3F), point(2, {400, 302}, 0.8F)};
    layout.setFrame(moved, camera());
    layout.advance(kFrame);
    EXPECT_EQ(layout.stats().removed_overlap, 1U);
    ASSERT_NE(find(layout, 1), nullptr);
    EXPECT_EQ(find(layout, 1)->state, nl::LabelState::FadingOut);
    EXPECT_LT(find(layout, 1)->alpha, layout.params().visible_alpha);
    EXPECT_EQ(find(layout, 2)->state, nl::LabelState::Visible);
    for (int f = 0; f < 180; ++f) {
        layout.setFrame(moved, camera());
        layout.advance(kFrame);
        std::size_t clashes = 0;
        for (const auto& a : layout.output()) {
            for (const auto& b : layout.output()) {
                if (a.id < b.id && a.alpha >= 0.5F && b.alpha >= 0.5F && a.box.overlaps(b.box)) ++clashes;
            }
        }
        ASSERT_EQ(clashes, 0U) << "frame " << f;
    }
    EXPECT_EQ(find(layout, 2)->state, nl::LabelState::Visible);
}

TEST(LabelLayout, KeepOutAreasRepelBlockAndHideLabels) {
    nl::LabelLayout layout;
    const std::vector<nl::OrientedBox> marker = {nl::OrientedBox{{400, 300}, {30, 30}, {1, 0}}};
    layout.setKeepOut(marker);
    // A label whose every candidate would cover the marker is not placed.
    run(layout, {point(1, {400, 300}, 0.5F, {40, 20})}, 0.6);
    EXPECT_EQ(find(layout, 1), nullptr);
    // One placed far away and then dragged onto the marker never covers it while visible.
    nl::LabelLayout moving;
    moving.setKeepOut(marker);
    run(moving, {point(2, {400, 100})}, 0.6);
    ASSERT_NE(find(moving, 2), nullptr);
    for (int f = 0; f <= 30; ++f) {
        moving.setFrame(std::vector{point(2, {400.0F, 100.0F + 200.0F * static_cast<float>(f) / 30.0F})}, camera());
        moving.advance(kFrame);
        const auto* l = find(moving, 2);
        if (l && l->alpha >= 0.5F) {
            EXPECT_FALSE(l->box.overlaps(marker[0])) << "frame " << f;
        }
    }
    // Bad keep-out boxes are refused and counted.
    nl::LabelLayout bad;
    const std::vector<nl::OrientedBox> wrong = {nl::OrientedBox{{NAN, 0}, {1, 1}, {1, 0}},
                                                nl::OrientedBox{{0, 0}, {-1, 1}, {1, 0}},
                                                nl::OrientedBox{{0, 0}, {1, 1}, {3, 0}}};
    bad.setKeepOut(wrong);
    EXPECT_EQ(bad.stats().rejected_inputs, 3U);
}

TEST(LabelLayout, UprightLabelsStandOnTheirAnchor) {
    nl::LabelLayout layout;
    nl::LabelCandidate road = point(1, {400, 300}, 0.5F, {120, 20});
    road.kind = nl::LabelKind::Line;
    road.line_p0 = {300, 330};
    road.line_p1 = {500, 270};
    road.axis = glm::normalize(road.line_p1 - road.line_p0);
    road.upright = true;
    nl::LabelCandidate place = point(2, {800, 400}, 0.5F, {80, 20});
    place.upright = true;
    // Something above the place's upper right corner: it takes the upper left, never a lower one.
    nl::LabelCandidate blocker = point(3, {900, 360}, 0.9F, {60, 40});
    run(layout, {road, place, blocker}, 0.6, camera(76.0F));
    const auto* r = find(layout, 1);
    ASSERT_NE(r, nullptr);
    // The box keeps the given axis even in a steep view (no rotation rule for world-space text).
    EXPECT_NEAR(r->box.axis.x, road.axis.x, 1e-5F);
    EXPECT_NEAR(r->box.axis.y, road.axis.y, 1e-5F);
    // It stands on the line: its center lies on the screen-up side of it.
    const glm::vec2 normal(-road.axis.y, road.axis.x);
    EXPECT_LT(glm::dot(r->box.center - road.anchor, normal) * (normal.y > 0 ? 1.0F : -1.0F), -5.0F);
    const auto* p = find(layout, 2);
    ASSERT_NE(p, nullptr);
    EXPECT_LT(p->box.center.y, place.anchor.y) << "an upright label is never below its anchor";
}

TEST(LabelLayout, FiveFramesPerSecondKeepWallClockTiming) {
    // The same scene fed at 5 and at 30 fps: fades, placements and removals happen at the same
    // simulated times (steps are fixed; all steps due in a long frame run).
    const nt::SyntheticScene scene = nt::makeSyntheticScene(200, 7, 0.8F);
    nl::LabelLayout slow, fast;
    for (int t = 1; t <= 15; ++t) {  // 3 s in 0.2 s frames
        slow.setFrame(scene.candidates, scene.camera);
        slow.advance(0.2);
        for (int k = 0; k < 6; ++k) {
            fast.setFrame(scene.candidates, scene.camera);
            fast.advance(0.2 / 6.0);
        }
        EXPECT_NEAR(slow.timeS(), 0.2 * t, 1e-9);
        EXPECT_NEAR(fast.timeS(), 0.2 * t, 1e-9);
        ASSERT_EQ(slow.stats().visible + slow.stats().fading_in, fast.stats().visible + fast.stats().fading_in)
            << "t " << t;
    }
    EXPECT_TRUE(sameOutput(slow.output(), fast.output()));
    EXPECT_GT(slow.stats().visible, 20U);
}

TEST(LabelLayout, ConstrictedLabelIsRemoved) {
    nl::LayoutParams p;
    p.constricted_time_s = 0.05F;
    p.overlap_removal_s = 10.0F;
    p.hard_overlap_px = 1000.0F;  // this test is about the forces cancelling out, not overlaps
    nl::LabelLayout layout(p);
    run(layout, {point(1, {100, 100}, 0.9F), point(2, {700, 100}, 0.9F), point(3, {400, 300}, 0.1F)}, 0.6);
    ASSERT_EQ(layout.stats().visible, 3U);
    // Label 3 gets squeezed from both sides by 30 px: the forces cancel out.
    run(layout, {point(1, {330, 300}, 0.9F), point(2, {470, 300}, 0.9F), point(3, {400, 300}, 0.1F)}, 0.2);
    EXPECT_EQ(layout.stats().removed_constricted, 1U);
    ASSERT_NE(find(layout, 3), nullptr);
    EXPECT_EQ(find(layout, 3)->state, nl::LabelState::FadingOut);
    EXPECT_EQ(find(layout, 1)->state, nl::LabelState::Visible);
}

TEST(LabelLayout, SpeedBasedRemoval) {
    nl::LayoutParams p;
    p.removal_speed_px_s = 5.0F;
    nl::LabelLayout layout(p);
    run(layout, {point(1, {400, 300}), point(2, {400, 500})}, 0.6);
    run(layout, {point(1, {400, 300}), point(2, {400, 305})}, 0.3);  // collision pushes them fast
    EXPECT_GE(layout.stats().removed_speed, 1U);

    nl::LayoutParams q;
    q.max_anchor_speed_px_s = 600.0F;
    nl::LabelLayout fast(q);
    run(fast, {point(1, {400, 300})}, 0.6);
    for (int f = 0; f < 20; ++f) {  // the anchor races across the screen at 1200 px/s
        fast.setFrame(std::vector{point(1, {400.0F + 20.0F * static_cast<float>(f), 300})}, camera());
        fast.advance(kFrame);
    }
    EXPECT_EQ(fast.stats().removed_speed, 1U);
    EXPECT_EQ(find(fast, 1)->state, nl::LabelState::FadingOut);
}

TEST(LabelLayout, LineLabelsRotateByViewAngleWithHysteresis) {
    nl::LabelCandidate line;
    line.id = 1;
    line.kind = nl::LabelKind::Line;
    line.anchor = {400, 300};
    line.size = {120, 16};
    line.line_p0 = {400 - 86.6F, 300 + 50};  // drawn right to left, 30 degrees down-right on screen
    line.line_p1 = {400 + 86.6F, 300 - 50};
    nl::LabelLayout layout;
    run(layout, {line}, 0.1, camera(30));
    const auto* l = find(layout, 1);
    ASSERT_NE(l, nullptr);
    EXPECT_NEAR(l->box.angle(), -0.5236F, 1e-3F);  // along the segment, reading left to right
    EXPECT_EQ(l->candidate, 0);
    // Above the line: offset along the normal pointing to negative screen y.
    const glm::vec2 off = l->box.center - line.anchor;
    EXPECT_LT(off.y, 0.0F);
    EXPECT_NEAR(glm::length(off), 8.0F + 2.0F, 1e-3F);
    run(layout, {line}, 1.0, camera(73));  // inside the hysteresis band (70 +- 5): stays rotated
    EXPECT_NEAR(find(layout, 1)->box.angle(), -0.5236F, 1e-3F);
    run(layout, {line}, 0.05, camera(80));  // beyond it: turns towards horizontal, smoothly
    const float turning = find(layout, 1)->box.angle();
    EXPECT_GT(turning, -0.5236F);
    EXPECT_LT(turning, 0.0F);
    run(layout, {line}, 1.0, camera(80));
    EXPECT_NEAR(find(layout, 1)->box.angle(), 0.0F, 1e-5F);

    // Placed at a steep view: horizontal from the start.
    nl::LabelLayout steep;
    run(steep, {line}, 0.1, camera(80));
    EXPECT_NEAR(find(steep, 1)->box.angle(), 0.0F, 1e-6F);
}

TEST(LabelLayout, LineLabelTakesTheNextCandidateWhenBlocked) {
    nl::LabelCandidate line;
    line.id = 1;
    line.kind = nl::LabelKind::Line;
    line.anchor = {400, 300};
    line.size = {120, 16};
    line.line_p0 = {300, 300};
    line.line_p1 = {500, 300};
    nl::LabelLayout layout;
    // A blocker sits above the line first, so the label takes the candidate below.
    run(layout, {point(9, {300, 290}, 1.0F, {200, 20}), line}, 0.2);
    ASSERT_NE(find(layout, 1), nullptr);
    EXPECT_EQ(find(layout, 1)->candidate, 1);
    EXPECT_NEAR(find(layout, 1)->box.center.y, 300.0F + 10.0F, 1e-3F);
    EXPECT_NEAR(find(layout, 1)->box.center.x, 400.0F, 1e-3F);
}

TEST(LabelLayout, CircleLabelPlacedOnItsRadius) {
    nl::LabelCandidate c = point(1, {400, 300});
    c.kind = nl::LabelKind::Circle;
    c.circle_radius = 70.0F;
    nl::LabelLayout layout;
    run(layout, {c, point(2, {470, 330})}, 2.0);
    ASSERT_NE(find(layout, 1), nullptr);
    EXPECT_NEAR(glm::length(find(layout, 1)->box.center - c.anchor), 70.0F, 1.0F);
}

TEST(LabelLayout, DepthScalingKeepsAReadableMinimum) {
    auto near_label = point(1, {200, 300}, 0.5F, {100, 14});
    near_label.depth = 100.0F;  // 200 / 100 = 2 -> max_scale 1.5
    auto mid_label = point(2, {600, 300}, 0.5F, {100, 20});
    mid_label.depth = 250.0F;  // 0.8
    auto far_label = point(3, {1000, 300}, 0.5F, {100, 14});
    far_label.depth = 2000.0F;  // 0.1 -> min_scale 0.6 -> readable: capitals of 9.5 px
    far_label.cap_height = 10.0F;
    auto far_no_cap = point(4, {1000, 500}, 0.5F, {100, 14});
    far_no_cap.depth = 2000.0F;  // no cap height given: 0.7 of the box height
    nl::LabelLayout layout;
    run(layout, {near_label, mid_label, far_label, far_no_cap}, 0.1);
    EXPECT_FLOAT_EQ(find(layout, 1)->scale, 1.5F);
    EXPECT_FLOAT_EQ(find(layout, 1)->box.half_extents.x, 75.0F);
    EXPECT_FLOAT_EQ(find(layout, 2)->scale, 0.8F);
    EXPECT_FLOAT_EQ(find(layout, 3)->scale, 9.5F / 10.0F);
    EXPECT_FLOAT_EQ(find(layout, 3)->box.half_extents.y, 7.0F * 0.95F);
    EXPECT_FLOAT_EQ(find(layout, 4)->scale, 9.5F / (0.7F * 14.0F));
    // The depth reference can come with the camera (the renderer's look-at distance).
    nl::CameraState cam = camera();
    cam.depth_reference_m = 400.0F;
    nl::LabelLayout zoomed;
    run(zoomed, {mid_label}, 0.1, cam);
    EXPECT_FLOAT_EQ(find(zoomed, 2)->scale, 1.5F);  // 400 / 250 = 1.6 -> max_scale
}

TEST(LabelLayout, DenseSceneSettlesWithoutOverlaps) {
    // 600 candidates whose text covers 1.5 screens; the camera zooms out and turns for 2 s
    // (anchors converge: labels collide, get pushed and removed), then holds still for 5 s.
    nt::SyntheticScene scene = nt::makeSyntheticScene(600, 5, 1.5F);
    nl::LabelLayout layout;
    nl::LayoutMetrics moving;
    nl::LayoutMetrics settled;
    std::vector<nl::LabelCandidate> on_screen;
    for (int f = 0; f < 420; ++f) {
        if (f < 120) nt::zoomRotateScene(scene, scene.camera.viewport * 0.5F, 0.996F, 0.003F);
        on_screen.clear();  // the renderer culls anchors outside the view
        for (const auto& c : scene.candidates) {
            if (c.anchor.x >= 0 && c.anchor.y >= 0 && c.anchor.x <= scene.camera.viewport.x &&
                c.anchor.y <= scene.camera.viewport.y) {
                on_screen.push_back(c);
            }
        }
        layout.setFrame(on_screen, scene.camera);
        layout.advance(kFrame);
        moving.addFrame(layout.output(), kFrame);
        if (f >= 360) settled.addFrame(layout.output(), kFrame);
    }
    const nl::LayoutQuality during = moving.summary();
    EXPECT_EQ(during.max_overlaps, 0U) << "no visible text over other text in any frame";
    EXPECT_GT(layout.stats().removed_overlap, 0U) << "the scene is meant to make labels collide";
    // Removals fade out and placements fade in; only a label dropped below the visible opacity
    // at once, as its box lands on another's, makes an alpha jump.
    EXPECT_LE(during.pops, layout.stats().removed_overlap);
    const nl::LayoutQuality q = settled.summary();
    EXPECT_EQ(q.max_overlaps, 0U) << "overlapping visible labels after settling";
    EXPECT_GT(q.last_visible, 60U);
    EXPECT_EQ(q.pops, 0U);
    EXPECT_LT(q.mean_jitter_px, 0.02);
    const nl::LayoutStats s = layout.stats();
    EXPECT_GT(s.removed_overlap + s.removed_constricted + s.removed_speed, 0U);
}

TEST(LabelLayout, DeterministicForTheSameInputs) {
    auto simulate = [](bool shuffled) {
        nt::SyntheticScene scene = nt::makeSyntheticScene(400, 9, 2.0F);
        nl::LabelLayout layout;
        std::mt19937 rng(3);
        std::vector<std::vector<nl::PlacedLabel>> frames;
        for (int f = 0; f < 150; ++f) {
            nt::panScene(scene, {std::sin(0.05F * static_cast<float>(f)) * 3.0F, 1.0F});
            std::vector<nl::LabelCandidate> input = scene.candidates;
            if (shuffled) std::shuffle(input.begin(), input.end(), rng);
            layout.setFrame(input, scene.camera);
            layout.advance(f % 3 == 0 ? 1.0 / 30.0 : 1.0 / 60.0);  // uneven frame times
            frames.emplace_back(layout.output().begin(), layout.output().end());
        }
        return frames;
    };
    const auto a = simulate(false);
    const auto b = simulate(false);
    const auto c = simulate(true);  // input order does not matter either
    ASSERT_EQ(a.size(), b.size());
    std::size_t moving = 0;
    for (std::size_t f = 0; f < a.size(); ++f) {
        EXPECT_TRUE(sameOutput(a[f], b[f])) << "frame " << f;
        EXPECT_TRUE(sameOutput(a[f], c[f])) << "frame " << f << " (shuffled input)";
        moving += a[f].size();
    }
    EXPECT_GT(moving, 1000U);
}

TEST(LabelLayout, FixedStepIsIndependentOfFrameRate) {
    const nt::SyntheticScene scene = nt::makeSyntheticScene(300, 4, 1.5F);
    nl::LabelLayout at30;
    nl::LabelLayout at60;
    nl::LabelLayout at144;
    for (int f = 0; f < 30; ++f) {
        at30.setFrame(scene.candidates, scene.camera);
        EXPECT_EQ(at30.advance(1.0 / 30.0), 2);
    }
    for (int f = 0; f < 60; ++f) {
        at60.setFrame(scene.candidates, scene.camera);
        EXPECT_EQ(at60.advance(1.0 / 60.0), 1);
    }
    int steps = 0;
    for (int f = 0; f < 144; ++f) {
        at144.setFrame(scene.candidates, scene.camera);
        steps += at144.advance(1.0 / 144.0);
    }
    EXPECT_EQ(steps, 60);
    EXPECT_EQ(at30.stats().steps, 60U);
    EXPECT_EQ(at144.stats().steps, 60U);
    EXPECT_TRUE(sameOutput(at30.output(), at60.output()));
    EXPECT_TRUE(sameOutput(at30.output(), at144.output()));
    EXPECT_GT(at30.output().size(), 50U);
}

TEST(LabelLayout, SurvivesGarbageInput) {
    std::mt19937 rng(99);
    std::uniform_int_distribution<std::uint32_t> bits;
    auto any_float = [&] {
        const std::uint32_t b = bits(rng);
        float f;
        std::memcpy(&f, &b, sizeof f);
        return (b & 3U) == 0 ? f : static_cast<float>(b % 2000U) - 500.0F;  // some raw bit patterns
    };
    nl::LabelLayout layout;
    for (int frame = 0; frame < 60; ++frame) {
        std::vector<nl::LabelCandidate> c(50);
        for (auto& l : c) {
            l.id = bits(rng) % 64U;
            l.priority = any_float();
            l.kind = static_cast<nl::LabelKind>(bits(rng) % 5U);
            l.anchor = {any_float(), any_float()};
            l.depth = any_float();
            l.size = {any_float(), any_float()};
            l.line_p0 = {any_float(), any_float()};
            l.line_p1 = {any_float(), any_float()};
            l.circle_radius = any_float();
        }
        nl::CameraState cam{any_float(), {any_float(), any_float()}};
        layout.setFrame(c, cam);
        layout.advance(kFrame);
        for (const auto& l : layout.output()) {
            ASSERT_TRUE(std::isfinite(l.box.center.x) && std::isfinite(l.box.center.y)) << "id " << l.id;
            ASSERT_TRUE(std::isfinite(l.alpha));
        }
    }
    EXPECT_GT(layout.stats().rejected_inputs, 0U);
}

// Placement looks ahead (LayoutParams::placement_lookahead_s): a label whose anchor carries its
// text out of the view within that time is not placed for a moment only; one moving inwards is.
TEST(LabelLayout, LabelAboutToLeaveTheViewIsNotPlaced) {
    for (const float direction : {1.0F, -1.0F}) {
        for (const float lookahead : {1.5F, 0.0F}) {
            nl::LayoutParams p;
            p.placement_lookahead_s = lookahead;
            nl::LabelLayout layout(p);
            // A keep-out area holds the label back at first; then it waits for its retry timer
            // while its anchor runs at 300 px/s towards the right edge (direction 1) or away
            // from it.
            float x = direction > 0.0F ? 700.0F : 1100.0F;
            const auto frame = [&] {
                layout.setFrame(std::vector{point(1, {x, 300})}, camera());
                layout.advance(kFrame);
                x += direction * 300.0F * static_cast<float>(kFrame);
            };
            const nl::OrientedBox block{{850, 300}, {400, 100}, {1, 0}};
            layout.setKeepOut(std::span(&block, 1));
            for (int f = 0; f < 12; ++f) frame();
            ASSERT_EQ(find(layout, 1), nullptr) << "held back by the keep-out area";
            layout.setKeepOut({});
            bool shown = false;
            for (int f = 0; f < 90; ++f) {  // 1.5 s: the retry timer (1 to 1.25 s) runs out
                frame();
                shown |= find(layout, 1) != nullptr && find(layout, 1)->state != nl::LabelState::FadingOut;
            }
            // Moving right, its text would reach the edge at 1280 within 1.5 s of the retry.
            const bool expect_shown = direction < 0.0F || lookahead == 0.0F;
            EXPECT_EQ(shown, expect_shown) << "direction " << direction << " lookahead " << lookahead;
            if (!expect_shown) {
                EXPECT_GT(layout.stats().failures_off_screen, 0U);
            }
        }
    }
}

// Hysteresis (LayoutParams::established_s): when a label placed later runs into one shown for
// longer, the newcomer gives way even where it is more important.
TEST(LabelLayout, EstablishedLabelKeepsItsPlaceAgainstANewcomer) {
    for (const float established : {2.0F, -1.0F}) {
        nl::LayoutParams p;
        p.established_s = established;
        nl::LabelLayout layout(p);
        run(layout, {point(1, {400, 300}, 0.3F)}, 3.0);
        run(layout, {point(1, {400, 300}, 0.3F), point(2, {400, 500}, 0.8F)}, 0.6);
        ASSERT_NE(find(layout, 2), nullptr);
        ASSERT_EQ(find(layout, 2)->state, nl::LabelState::Visible);
        // The camera jumps: the two text boxes land on each other.
        run(layout, {point(1, {400, 300}, 0.3F), point(2, {400, 302}, 0.8F)}, kFrame);
        const std::uint64_t kept = established >= 0.0F ? 1 : 2;
        const std::uint64_t gone = 3 - kept;
        ASSERT_NE(find(layout, kept), nullptr);
        EXPECT_EQ(find(layout, kept)->state, nl::LabelState::Visible) << "established_s " << established;
        ASSERT_NE(find(layout, gone), nullptr);
        EXPECT_EQ(find(layout, gone)->state, nl::LabelState::FadingOut) << "established_s " << established;
        EXPECT_EQ(find(layout, gone)->reason, nl::RemovalReason::Overlap);
        EXPECT_LT(find(layout, gone)->alpha, layout.params().visible_alpha);
    }
}
