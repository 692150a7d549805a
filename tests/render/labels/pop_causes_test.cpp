// SPDX-License-Identifier: Apache-2.0
// PopCauses: each drawn pop attributed to the layout's removal reason, to what held a label back
// before it was placed, or to the renderer's input change; the causes add up to the pops of
// DrawnLabelMetrics on the same frames; the floor counts one entry per label not visible in the
// first frame and one exit per label not visible in the last.
#include <vector>

#include <gtest/gtest.h>

#include "drawn_label_metrics.h"
#include "pop_causes.h"

namespace nl = navmap::render::labels;

namespace {

const glm::vec2 kViewport{1280.0F, 480.0F};

// A point label drawn at `anchor` with one glyph box above it.
nl::DrawnLabel drawn(std::uint64_t id, glm::vec2 anchor, float opacity = 1.0F) {
    nl::DrawnLabel l;
    l.id = id;
    l.text = "label " + std::to_string(id);
    l.kind = nl::LabelKind::Point;
    l.opacity = opacity;
    l.anchor = anchor;
    l.center = anchor - glm::vec2(0, 7);
    l.cap_height_px = 12.0F;
    const glm::vec2 lo = anchor - glm::vec2(10, 12), hi = anchor + glm::vec2(10, -2);
    l.glyph_boxes.push_back({lo, glm::vec2(hi.x, lo.y), hi, glm::vec2(lo.x, hi.y)});
    return l;
}

nl::PlacedLabel placed(std::uint64_t id, nl::LabelState state, nl::RemovalReason reason = nl::RemovalReason::None,
                       nl::RemovalReason held_by = nl::RemovalReason::None) {
    nl::PlacedLabel p;
    p.id = id;
    p.state = state;
    p.reason = reason;
    p.held_by = held_by;
    return p;
}

struct Frame {
    std::vector<nl::DrawnLabel> drawn;
    std::vector<nl::PlacedLabel> placed;
    std::vector<nl::LabelInputChange> changes;
};

// One frame into the cause attribution and into the drawn-label metrics it must agree with.
void feed(nl::PopCauses& causes, nl::DrawnLabelMetrics& metrics, const Frame& f) {
    causes.addFrame(f.drawn, f.placed, f.changes, kViewport, true);
    metrics.addFrame(f.drawn, {}, kViewport, 1.0 / 30.0);
}

std::uint64_t pops(const nl::PopCauseFigures& f, nl::PopCause c) { return f.pops[static_cast<std::size_t>(c)]; }

}  // namespace

TEST(PopCauses, LeavesTakeTheLayoutsReasonOrTheInputChange) {
    nl::PopCauses causes;
    nl::DrawnLabelMetrics metrics;
    using S = nl::LabelState;
    using R = nl::RemovalReason;
    const glm::vec2 in{640, 240};
    std::vector<Frame> frames(2);
    // Frame 0: five labels visible.
    for (std::uint64_t id = 1; id <= 5; ++id) {
        frames[0].drawn.push_back(drawn(id, in + glm::vec2(60.0F * static_cast<float>(id), 0)));
        frames[0].placed.push_back(placed(id, S::Visible));
    }
    // Frame 1: 1 pushed off the screen's edge, 2 removed for a more important label, 3 over the
    // marker, 4 whose tile went away, 5 whose anchor left the view; all fading out below 0.5.
    const R reasons[5] = {R::OffScreen, R::Overlap, R::KeepOut, R::Gone, R::Gone};
    for (std::uint64_t id = 1; id <= 5; ++id) {
        frames[1].drawn.push_back(drawn(id, in + glm::vec2(60.0F * static_cast<float>(id), 0), 0.49F));
        frames[1].placed.push_back(placed(id, S::FadingOut, reasons[id - 1]));
    }
    frames[1].changes = {{4, false, nl::InputCause::Tiles}, {5, false, nl::InputCause::View}};
    for (const Frame& f : frames) feed(causes, metrics, f);
    const nl::PopCauseFigures f = causes.summary();
    EXPECT_EQ(f.leaves, 5U);
    EXPECT_EQ(f.enters, 0U);
    EXPECT_EQ(pops(f, nl::PopCause::Edge), 2U);  // 1 and 5
    EXPECT_EQ(pops(f, nl::PopCause::Overlap), 1U);
    EXPECT_EQ(pops(f, nl::PopCause::KeepOut), 1U);
    EXPECT_EQ(pops(f, nl::PopCause::Gone), 1U);
    EXPECT_EQ(pops(f, nl::PopCause::Other), 0U);
    EXPECT_EQ(f.interior_point_pops[static_cast<std::size_t>(nl::PopCause::Edge)], 2U);
    EXPECT_EQ(f.enters + f.leaves, metrics.summary().pops);
    // Every label was visible in the first frame and none in the last: five exits.
    EXPECT_EQ(f.floor, 5U);
}

TEST(PopCauses, EntersTakeWhatHeldTheLabelBack) {
    nl::PopCauses causes;
    nl::DrawnLabelMetrics metrics;
    using S = nl::LabelState;
    using R = nl::RemovalReason;
    const glm::vec2 in{640, 240};
    // A settling frame: 4's anchor comes into the view (remembered, not counted).
    causes.addFrame({}, {}, std::vector<nl::LabelInputChange>{{4, true, nl::InputCause::View}}, kViewport, false);
    std::vector<Frame> frames(3);
    frames[0].drawn = {drawn(9, in)};
    frames[0].placed = {placed(9, S::Visible)};
    // Frame 1: 1 came with a tile, 2 waited for a label to make room, 3 waited until its text fit
    // in the view, 4 was placed at once after its anchor entered (settling frame), 5 crossed 0.5
    // in the cross-fade only (the layout had it visible), 6 came back after its tile had gone.
    frames[1].changes = {{1, true, nl::InputCause::Tiles}, {6, true, nl::InputCause::Tiles}};
    const R held[6] = {R::None, R::Overlap, R::OffScreen, R::None, R::None, R::Gone};
    for (std::uint64_t id = 1; id <= 6; ++id) {
        frames[1].drawn.push_back(drawn(id, in + glm::vec2(60.0F * static_cast<float>(id), 0), 0.5F));
        frames[1].placed.push_back(placed(id, id == 5 ? S::Visible : S::FadingIn, R::None, held[id - 1]));
    }
    frames[1].drawn.push_back(drawn(9, in));
    frames[1].placed.push_back(placed(9, S::Visible));
    frames[2] = frames[1];
    frames[2].changes.clear();
    frames[2].drawn.pop_back();  // 9 leaves, its layout entry gone too: an unexplained leave
    frames[2].placed.pop_back();
    for (const Frame& f : frames) feed(causes, metrics, f);
    const nl::PopCauseFigures f = causes.summary();
    EXPECT_EQ(f.enters, 6U);
    EXPECT_EQ(f.leaves, 1U);
    EXPECT_EQ(pops(f, nl::PopCause::Gone), 2U);     // 1, 6
    EXPECT_EQ(pops(f, nl::PopCause::Overlap), 1U);  // 2
    EXPECT_EQ(pops(f, nl::PopCause::Edge), 2U);     // 3, 4
    EXPECT_EQ(pops(f, nl::PopCause::Other), 2U);    // 5 and 9
    EXPECT_EQ(f.enters + f.leaves, metrics.summary().pops);
    // 1..6 enter once (not visible in the first frame), 9 leaves once.
    EXPECT_EQ(f.floor, 7U);
    EXPECT_EQ(f.visible_runs, 7U);
}

TEST(PopCauses, FloorCountsEachLabelOnceWhateverItsFlicker) {
    nl::PopCauses causes;
    const glm::vec2 a{300, 200};
    // 1 visible in every frame, 2 flickers (in, out, in, out), 3 shows in the middle only.
    const std::vector<std::vector<nl::DrawnLabel>> frames = {
        {drawn(1, a)},
        {drawn(1, a), drawn(2, a + glm::vec2(100, 0))},
        {drawn(1, a), drawn(3, a + glm::vec2(200, 0))},
        {drawn(1, a), drawn(2, a + glm::vec2(100, 0))},
        {drawn(1, a)},
    };
    for (const auto& f : frames) causes.addFrame(f, {}, {}, kViewport, true);
    const nl::PopCauseFigures f = causes.summary();
    EXPECT_EQ(f.enters + f.leaves, 6U);
    EXPECT_EQ(pops(f, nl::PopCause::Other), 6U);  // no layout output: nothing explains them
    EXPECT_EQ(f.floor, 4U);                       // 2 and 3: one entry and one exit each
    EXPECT_EQ(f.visible_runs, 4U);
}
