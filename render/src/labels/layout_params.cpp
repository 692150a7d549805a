// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/labels/layout_params.h"

#include <cmath>

namespace navmap::render::labels {

namespace {

bool positive(double v) { return std::isfinite(v) && v > 0.0; }
bool nonNegative(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

std::string LayoutParams::validate() const {
    const auto bad = [](const char* field, double v, const char* need) {
        return std::string("LayoutParams.") + field + " = " + std::to_string(v) + ": must be " + need;
    };
    if (!positive(step_s) || step_s > 0.25) return bad("step_s", step_s, "in (0, 0.25]");
    if (max_steps_per_advance < 1) return bad("max_steps_per_advance", max_steps_per_advance, ">= 1");
    if (!nonNegative(collision_gain)) return bad("collision_gain", collision_gain, ">= 0");
    if (!nonNegative(k_feature)) return bad("k_feature", k_feature, ">= 0");
    if (!nonNegative(k_normal)) return bad("k_normal", k_normal, ">= 0");
    if (!nonNegative(k_tangent)) return bad("k_tangent", k_tangent, ">= 0");
    if (!nonNegative(k_circle)) return bad("k_circle", k_circle, ">= 0");
    if (!nonNegative(friction)) return bad("friction", friction, ">= 0");
    if (!positive(mass_min)) return bad("mass_min", mass_min, "> 0");
    if (!positive(mass_max) || mass_max < mass_min) return bad("mass_max", mass_max, ">= mass_min");
    if (!positive(max_accel)) return bad("max_accel", max_accel, "> 0");
    if (max_placements_per_step < 0) return bad("max_placements_per_step", max_placements_per_step, ">= 0");
    if (!nonNegative(candidate_gap_px)) return bad("candidate_gap_px", candidate_gap_px, ">= 0");
    if (!nonNegative(line_gap_px)) return bad("line_gap_px", line_gap_px, ">= 0");
    if (!nonNegative(retry_delay_s)) return bad("retry_delay_s", retry_delay_s, ">= 0");
    if (!std::isfinite(established_s)) return bad("established_s", established_s, "finite (negative: off)");
    if (!nonNegative(placement_lookahead_s) || placement_lookahead_s > 10.0F) {
        return bad("placement_lookahead_s", placement_lookahead_s, "within [0, 10]");
    }
    if (!nonNegative(fade_in_s)) return bad("fade_in_s", fade_in_s, ">= 0");
    if (!nonNegative(fade_out_s)) return bad("fade_out_s", fade_out_s, ">= 0");
    if (!nonNegative(buffer_px)) return bad("buffer_px", buffer_px, ">= 0");
    if (!nonNegative(placement_zone_px) || placement_zone_px < buffer_px) {
        return bad("placement_zone_px", placement_zone_px, ">= buffer_px");
    }
    if (!positive(removal_speed_px_s)) return bad("removal_speed_px_s", removal_speed_px_s, "> 0");
    if (!nonNegative(max_anchor_speed_px_s)) return bad("max_anchor_speed_px_s", max_anchor_speed_px_s, ">= 0");
    if (!nonNegative(constricted_min_force)) return bad("constricted_min_force", constricted_min_force, ">= 0");
    if (!nonNegative(constricted_ratio) || constricted_ratio > 1.0F) {
        return bad("constricted_ratio", constricted_ratio, "in [0, 1]");
    }
    if (!nonNegative(constricted_time_s)) return bad("constricted_time_s", constricted_time_s, ">= 0");
    if (!nonNegative(overlap_removal_s)) return bad("overlap_removal_s", overlap_removal_s, ">= 0");
    if (!positive(depth_reference_m)) return bad("depth_reference_m", depth_reference_m, "> 0");
    if (!positive(min_scale)) return bad("min_scale", min_scale, "> 0");
    if (!positive(max_scale) || max_scale < min_scale) return bad("max_scale", max_scale, ">= min_scale");
    if (!nonNegative(min_cap_height_px)) return bad("min_cap_height_px", min_cap_height_px, ">= 0");
    if (!nonNegative(hard_overlap_px)) return bad("hard_overlap_px", hard_overlap_px, ">= 0");
    if (!positive(visible_alpha) || visible_alpha > 1.0F) return bad("visible_alpha", visible_alpha, "in (0, 1]");
    if (!nonNegative(rotate_max_tilt_deg)) return bad("rotate_max_tilt_deg", rotate_max_tilt_deg, ">= 0");
    if (!nonNegative(max_rotation_deg) || max_rotation_deg > 90.0F) {
        return bad("max_rotation_deg", max_rotation_deg, "in [0, 90]");
    }
    if (!nonNegative(rotate_hysteresis_deg)) return bad("rotate_hysteresis_deg", rotate_hysteresis_deg, ">= 0");
    if (!positive(angular_speed_deg_s)) return bad("angular_speed_deg_s", angular_speed_deg_s, "> 0");
    if (!nonNegative(grid_cell_px)) return bad("grid_cell_px", grid_cell_px, ">= 0");
    return {};
}

}  // namespace navmap::render::labels
