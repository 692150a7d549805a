// SPDX-License-Identifier: Apache-2.0
#pragma once
// Temporally coherent force-based label layout (seed chapter 4), on the CPU, GL-free.
// Hand-written after the seed; no Debian package implements it.

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/render/labels/growing_grid.h"
#include "navmap/render/labels/label_types.h"
#include "navmap/render/labels/layout_params.h"
#include "navmap/render/labels/oriented_box.h"
#include "navmap/render/labels/spatial_grid.h"

namespace navmap::render::labels {

/// Thrown only at setup (invalid LayoutParams).
class LabelLayoutError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Counters of one layout, for tests, metrics and the status endpoint.
struct LayoutStats {
    std::uint64_t steps = 0;
    std::size_t pending = 0;
    std::size_t waiting = 0;
    std::size_t fading_in = 0;
    std::size_t visible = 0;
    std::size_t fading_out = 0;
    std::uint64_t placed = 0;               ///< successful initial placements
    std::uint64_t placement_failures = 0;   ///< attempts without a free candidate, of which:
    std::uint64_t failures_off_screen = 0;  ///<   no candidate in the view now and for placement_lookahead_s
    std::uint64_t failures_keep_out = 0;    ///<   a keep-out area (marker, route) blocked one
    std::uint64_t failures_labels = 0;      ///<   only other labels' zones blocked them
    std::uint64_t removed_speed = 0;
    std::uint64_t removed_constricted = 0;
    std::uint64_t removed_overlap = 0;
    std::uint64_t removed_keep_out = 0;  ///< of removed_overlap: over a keep-out area in a drawn frame
    std::uint64_t removed_off_screen = 0;
    std::uint64_t removed_gone = 0;     ///< placed labels whose candidate stopped coming (left the view, culled)
    std::uint64_t rejected_inputs = 0;  ///< candidates refused by setFrame() (bad values, duplicate ids)
    std::size_t last_pairs = 0;         ///< broad-phase pairs in the last step
    std::size_t last_collisions = 0;    ///< of those, colliding buffered boxes (eq. 4.2)
    // Work of the last advance() (its steps and the drawn-frame overlap rule), counted the same
    // on every machine: tests assert how it grows with the label count, benchmarks print it.
    std::uint64_t last_pair_tests = 0;  ///< box pairs the broad phases handed on (bounding-box or SAT test)
    std::uint64_t last_sat_tests = 0;   ///< separating-axis tests (seed 4.4.4) run
    std::uint64_t last_grid_cells = 0;  ///< uniform-grid cells visited
};

/// Result of setFrame(): what was refused and why (first problem only).
struct FrameReport {
    std::size_t accepted = 0;
    std::size_t rejected = 0;
    std::string first_error;  ///< e.g. "label id 42: non-finite anchor (nan, 3)"
};

/// Force-based layout of screen-space labels (seed 4.4-4.5):
///  - initial placement by priority, a bounded number per step, four-position model for
///    points/areas, three candidates for lines (horizontal or rotated by view angle), retry
///    timer when no candidate is free, fade in/out (4.4.3);
///  - collisions between buffered OOBBs by SAT (4.4.4) on a uniform grid broad phase, force
///    of eq. 4.2-4.6; free/line/circle behaviors with friction (4.4.5); mass from priority,
///    clamped Euler step (4.4.6, 4.5.1);
///  - enhancements of 4.5.3: buffer zone, placement zone, speed-based and constriction
///    removal with timed re-insertion; depth scaling with a readable minimum (4.3.3).
///
/// Use per frame: setFrame(candidates, camera) with the projected anchors, then
/// advance(frame_dt), then read output(). The simulation runs in fixed steps of
/// params.step_s, so the result depends only on the sequence of inputs and frame times,
/// never on wall-clock time: the same inputs give the same layout bit for bit.
/// Not thread-safe: one owner (the render thread).
class LabelLayout {
public:
    explicit LabelLayout(LayoutParams params = {});

    /// Replaces the set of candidates. Ids missing from the new set fade out; new ids queue
    /// for placement. Candidates with non-finite values, a non-positive size or a duplicate
    /// id are refused (counted, reported) and treated as absent.
    FrameReport setFrame(std::span<const LabelCandidate> candidates, const CameraState& camera);

    /// Advances the simulation by `dt_s` of frame time (fixed steps, remainder carried over)
    /// and rebuilds output(). Returns the number of steps run. Negative or non-finite dt
    /// runs nothing.
    int advance(double dt_s);

    /// Areas no label may cover (screen boxes: the vehicle marker, the route just ahead of the
    /// car). They push labels away like a label that never moves, no label is placed over them,
    /// and a label over one drops below the visible opacity at once. Kept until replaced; boxes
    /// with non-finite or negative values are refused (counted in rejected_inputs).
    void setKeepOut(std::span<const OrientedBox> areas);

    /// Runs exactly one fixed step (tests, benchmarks); does not rebuild output().
    void step();

    /// Labels with alpha > 0 (fading in, visible, fading out) in id order, as of the last
    /// advance().
    [[nodiscard]] std::span<const PlacedLabel> output() const { return m_output; }
    /// Rebuilds output() from the current state (advance() does this itself).
    void updateOutput();

    [[nodiscard]] LayoutStats stats() const;
    [[nodiscard]] const LayoutParams& params() const { return m_params; }
    /// Simulated time: steps run so far times step_s.
    [[nodiscard]] double timeS() const { return static_cast<double>(m_stats.steps) * m_params.step_s; }

private:
    struct Label {
        LabelCandidate in;
        LabelState state = LabelState::Pending;
        RemovalReason reason = RemovalReason::None;
        RemovalReason held_by = RemovalReason::None;  ///< PlacedLabel::held_by
        bool present = true;
        bool rotated = false;
        bool dead = false;
        std::uint8_t candidate = 0;
        float angle = 0.0F;
        glm::vec2 axis{1.0F, 0.0F};  ///< (cos angle, sin angle)
        float scale = 1.0F;
        float mass = 1.0F;
        glm::vec2 half{0.0F};
        glm::vec2 dir{1.0F, 0.0F};
        glm::vec2 offset{0.0F};
        glm::vec2 velocity{0.0F};
        glm::vec2 anchor_prev{0.0F};
        float anchor_speed = 0.0F;
        glm::vec2 anchor_velocity{0.0F};  ///< screen motion of the anchor, px/s, low-passed
        float alpha = 0.0F;
        float timer = 0.0F;
        float overlap_time = 0.0F;
        double placed_at_s = 0.0;  ///< timeS() of its last placement
        float constricted_time = 0.0F;
    };

    void updateShape(Label& l, bool placing) const;
    [[nodiscard]] OrientedBox textBox(const Label& l) const;
    void remove(Label& l, RemovalReason why);
    /// The forces and motion of one step (label_forces.cpp).
    void integrate(float dt);
    void collectActive();    ///< m_active: the placed labels, shapes updated
    void buildForceGrid();   ///< their buffered boxes, on m_grid
    void collisionForces();  ///< eq. 4.2-4.6 over the grid's pairs; marks labels pressed by a more important one
    void keepOutForces();    ///< keep-out areas push like labels that never move
    [[nodiscard]] glm::vec2 behaviorForce(const Label& l) const;  ///< eq. 4.7-4.17 towards its candidate
    void moveLabel(std::size_t a, float dt);  ///< Euler step of m_active[a], then the removal rules of 4.5.3
    /// The initial placement of one step (label_placement.cpp).
    struct Placement;
    void place();
    [[nodiscard]] std::size_t queuePlacements();  ///< m_queue in placement order; how many to place now
    void collectFading();                         ///< m_fading_grid: labels fading out, still drawn
    void placeLabel(Label& l, Placement& p);      ///< at its first free candidate, or waits
    /// Whether a candidate's text box is in the view and its placement zone free (now and ahead).
    [[nodiscard]] bool candidateFree(const Label& l, const OrientedBox& text, Placement& p);
    /// Whether the candidate stays in the view and free of the placed labels for placement_lookahead_s.
    [[nodiscard]] bool freeAhead(const Label& l, const OrientedBox& text, Placement& p);
    [[nodiscard]] glm::vec2 maxPlacedAnchorSpeed() const;  ///< per axis, over the placed labels
    void fade(float dt);
    /// The hard rule of a drawn frame (label_overlaps.cpp): a label over one ranked before it, or
    /// over a keep-out area, drops below the visible opacity.
    void resolveOverlaps();
    [[nodiscard]] float retryDelay(std::uint64_t id) const;
    /// Shown for LayoutParams::established_s (it wins over a newcomer whatever its priority).
    [[nodiscard]] bool established(const Label& l) const;
    /// Which of two placed labels gives way to the other (the newcomer, else the less important one).
    [[nodiscard]] bool yields(const Label& a, const Label& b) const;
    /// OrientedBox::overlapDepth, counted in LayoutStats::last_sat_tests.
    [[nodiscard]] float satDepth(const OrientedBox& a, const OrientedBox& b);
    /// Whether a box overlaps or touches one of `boxes` (a new label's placement zone against
    /// those placed this step, the keep-out areas, labels fading out): bounding boxes first.
    [[nodiscard]] bool touchesAny(const OrientedBox& box, std::span<const OrientedBox> boxes,
                                  std::span<const glm::vec2> aabbs);

    LayoutParams m_params;
    CameraState m_camera;
    double m_frame_time_s = 0.0;    ///< sum of advance() times
    std::int64_t m_steps_done = 0;  ///< steps accounted for (run or dropped)
    std::vector<Label> m_labels;    ///< sorted by id
    std::vector<Label> m_next;      ///< merge buffer of setFrame()
    std::vector<LabelCandidate> m_sorted;
    std::vector<PlacedLabel> m_output;
    LayoutStats m_stats;

    // Per-step scratch (kept to avoid reallocation).
    SpatialGrid m_grid;
    std::vector<std::uint32_t> m_active;  ///< indices into m_labels of FadingIn/Visible labels
    std::vector<OrientedBox> m_boxes;     ///< buffered boxes of the active labels
    std::vector<glm::vec2> m_centers;
    std::vector<glm::vec2> m_aabb;
    std::vector<glm::vec2> m_force;
    std::vector<float> m_force_abs;
    std::vector<std::uint8_t> m_overlapped;
    std::vector<std::uint32_t> m_queue;
    std::vector<OrientedBox> m_placed_now;
    GrowingGrid m_placed_grid;  ///< over m_placed_now
    std::vector<OrientedBox> m_keep_out;
    std::vector<glm::vec2> m_keep_out_aabb;
    std::vector<OrientedBox> m_fading_boxes;
    std::vector<glm::vec2> m_fading_centers;
    std::vector<glm::vec2> m_fading_aabb;
    SpatialGrid m_fading_grid;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> m_rank_keys;
    std::vector<std::uint32_t> m_rank_labels;  ///< resolveOverlaps: visible labels (m_labels indices)
    std::vector<OrientedBox> m_rank_boxes;     ///< their text boxes
    std::vector<glm::vec2> m_rank_centers;
    std::vector<glm::vec2> m_rank_aabb;
    std::vector<std::uint8_t> m_rank_state;  ///< involved in an overlap, kept
    std::vector<std::uint32_t> m_rank_pos;   ///< rank among the involved ones
    SpatialGrid m_rank_grid;
    std::uint64_t m_pair_tests = 0;  ///< work of the current advance()
    std::uint64_t m_sat_tests = 0;
    std::uint64_t m_placed_cells = 0;
};

}  // namespace navmap::render::labels
