// SPDX-License-Identifier: Apache-2.0
#include "label_space_switch.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

namespace navmap::render::labels {

namespace {

class LabelSpaceSwitchError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace

LabelSpaceSwitch::LabelSpaceSwitch(SpaceSwitchParams params, LabelSpace initial)
    : m_params(params), m_space(initial), m_linear(initial == LabelSpace::World ? 1.0F : 0.0F) {
    const SpaceSwitchParams& p = m_params;
    if (!std::isfinite(p.enter_tilt_deg) || !std::isfinite(p.exit_tilt_deg) || !std::isfinite(p.enter_height_m) ||
        !std::isfinite(p.exit_height_m) || !std::isfinite(p.crossfade_s) || p.crossfade_s < 0.0F) {
        throw LabelSpaceSwitchError("SpaceSwitchParams: values must be finite and crossfade_s >= 0");
    }
    if (p.exit_tilt_deg > p.enter_tilt_deg || p.exit_height_m < p.enter_height_m) {
        throw LabelSpaceSwitchError("SpaceSwitchParams: need exit_tilt_deg (" + std::to_string(p.exit_tilt_deg) +
                                    ") <= enter_tilt_deg (" + std::to_string(p.enter_tilt_deg) +
                                    ") and exit_height_m (" + std::to_string(p.exit_height_m) +
                                    ") >= enter_height_m (" + std::to_string(p.enter_height_m) + ")");
    }
}

float LabelSpaceSwitch::tiltDeg(glm::vec3 look_dir, glm::vec3 ground_up) {
    const float ll = glm::length(look_dir);
    const float lu = glm::length(ground_up);
    if (ll <= 0.0F || lu <= 0.0F) {
        return 0.0F;
    }
    const float c = std::clamp(glm::dot(look_dir, -ground_up) / (ll * lu), -1.0F, 1.0F);
    return std::acos(c) * 180.0F / std::numbers::pi_v<float>;
}

LabelSpace LabelSpaceSwitch::decide(LabelSpace current, float tilt_deg, float height_m, const SpaceSwitchParams& p) {
    if (current == LabelSpace::Screen) {
        // seed 5.5 (1) angle big enough AND (2) close enough to the ground.
        return tilt_deg >= p.enter_tilt_deg && height_m <= p.enter_height_m ? LabelSpace::World : LabelSpace::Screen;
    }
    // Leaving needs a clear margin on either condition: the hysteresis band.
    return tilt_deg < p.exit_tilt_deg || height_m > p.exit_height_m ? LabelSpace::Screen : LabelSpace::World;
}

LabelSpace LabelSpaceSwitch::update(float tilt_deg, float height_m, double dt_s) {
    if (std::isfinite(tilt_deg) && std::isfinite(height_m)) {
        m_space = decide(m_space, tilt_deg, height_m, m_params);
    }
    if (std::isfinite(dt_s) && dt_s > 0.0) {
        const float target = m_space == LabelSpace::World ? 1.0F : 0.0F;
        const float rate = m_params.crossfade_s > 0.0F ? static_cast<float>(dt_s) / m_params.crossfade_s : 1.0F;
        m_linear += std::clamp(target - m_linear, -rate, rate);
    }
    return m_space;
}

float LabelSpaceSwitch::worldWeight() const {
    const float t = std::clamp(m_linear, 0.0F, 1.0F);
    return t * t * (3.0F - 2.0F * t);  // smoothstep: no velocity jump at either end
}

}  // namespace navmap::render::labels
