// SPDX-License-Identifier: Apache-2.0
#pragma once
// Tuning constants of the force-based label layout (seed chapter 4). Units: pixels, seconds.

#include <string>

namespace navmap::render::labels {

/// All constants of LabelLayout. Defaults suit 1280x720..1920x1080 screens with 12-20 px text.
struct LayoutParams {
    // Fixed simulation step (seed 4.4.6 dt), independent of the frame rate.
    double step_s = 1.0 / 60.0;
    /// Steps one advance() runs at most; a longer frame drops the rest instead of spiralling.
    /// 30 steps (0.5 s) keep fades, removals and movement in wall-clock time down to 2 fps.
    int max_steps_per_advance = 30;

    // Forces (seed 4.4.5). Spring constants are in 1/s^2 at mass 1.
    float collision_gain = 2500.0F;  ///< px/s^2 for a collision force of magnitude 1 (eq. 4.5)
    float k_feature = 20.0F;         ///< k1, free label spring (eq. 4.7)
    float k_normal = 60.0F;          ///< k2, line normal spring (eq. 4.12)
    float k_tangent = 12.0F;         ///< k3, line tangent spring (eq. 4.15)
    float k_circle = 40.0F;          ///< k4, circle spring (eq. 4.17)
    float friction = 10.0F;          ///< c of eq. 4.8
    float mass_min = 1.0F;           ///< mass of priority 0 (seed 4.4.6)
    float mass_max = 3.0F;           ///< mass of priority 1
    float max_accel = 3000.0F;       ///< clamp of eq. 4.19 (seed 4.5.1), px/s^2

    // Initial placement (seed 4.4.3).
    int max_placements_per_step = 32;  ///< placement attempts per step (seed 4.5: a fixed number)
    float candidate_gap_px = 4.0F;     ///< gap between a point anchor and its label box
    float line_gap_px = 2.0F;          ///< gap between a line and its side candidates
    float retry_delay_s = 1.0F;        ///< timer before a label without free candidate retries
    /// Temporal coherence of placement: a new label must also fit where the anchors' screen
    /// motion (low-passed over 0.1 s) carries it and the placed labels within this time, checked
    /// at 1/3, 2/3 and all of it: in the viewport, clear of the placed labels and of the keep-out
    /// areas. A label that would be cut by the viewport's edge or run into another label
    /// straight away is not shown for a moment only (two pops). 0 = off.
    float placement_lookahead_s = 1.5F;
    /// Hysteresis of the layout (temporal coherence): a label shown for this long is established;
    /// when it and a label placed later run into each other, the later one gives way, whatever
    /// their priorities (priority decides between two established labels or two newcomers).
    /// Negative = off (priority alone).
    float established_s = 2.0F;
    float fade_in_s = 0.4F;
    float fade_out_s = 0.4F;

    // Enhancements (seed 4.5.3).
    float buffer_px = 3.0F;              ///< enlarged OOBBs used for the forces
    float placement_zone_px = 10.0F;     ///< no new label within this margin of a placed one (>= buffer_px)
    float removal_speed_px_s = 400.0F;   ///< speed-based removal: label speed relative to its anchor
    float max_anchor_speed_px_s = 0.0F;  ///< also remove when the anchor itself moves faster; 0 = off
    float constricted_min_force = 0.6F;  ///< sum of |f^(i,k)| above which a label may be constricted
    float constricted_ratio = 0.25F;     ///< |sum f| / sum |f| below which the forces cancel out
    float constricted_time_s = 0.5F;     ///< how long it must stay constricted before removal
    float overlap_removal_s = 0.5F;      ///< text box closer than buffer_px to a more important one this long: fade out
    /// Text boxes may never overlap in a drawn frame: a label whose box (with halo) overlaps a
    /// more important label's or a keep-out area by more than this is removed at once, its
    /// opacity dropped below `visible_alpha` in the same frame, and fades out from there.
    float hard_overlap_px = 0.0F;
    float visible_alpha = 0.5F;  ///< opacity from which a label counts as visible (and may not overlap)

    // Depth scaling (seed 4.3.3): scale = depth_reference / depth, clamped, never below readable.
    float depth_reference_m = 200.0F;
    float min_scale = 0.6F;
    float max_scale = 1.5F;
    float min_cap_height_px = 9.5F;  ///< readable minimum: cap height on screen, px (never scaled below)

    // Line labels: rotated along the segment or horizontal (seed 4.3.3, 4.4.3).
    float rotate_max_tilt_deg = 70.0F;   ///< rotated only while the camera tilt is below this
    float max_rotation_deg = 75.0F;      ///< segments steeper than this on screen get horizontal text
    float rotate_hysteresis_deg = 5.0F;  ///< margin on both thresholds against flicker
    float angular_speed_deg_s = 180.0F;  ///< how fast a label turns to its target angle

    // Broad phase: uniform grid cell size in pixels; 0 picks the mean label extent each step.
    float grid_cell_px = 0.0F;

    /// Empty when the parameters are usable, else a message naming the first bad field.
    [[nodiscard]] std::string validate() const;
};

}  // namespace navmap::render::labels
