// SPDX-License-Identifier: Apache-2.0
#include "synthetic_label_scene.h"

#include <cmath>
#include <numbers>

namespace navmap::test {

using render::labels::LabelCandidate;
using render::labels::LabelKind;

namespace {

// xorshift64*: fixed sequence on every platform, unlike std:: distributions.
class Rng {
public:
    explicit Rng(std::uint64_t seed) : m_s(seed * 0x9E3779B97F4A7C15ULL + 0x2545F4914F6CDD1DULL) {
        if (m_s == 0) m_s = 1;
    }
    float uniform(float lo, float hi) {
        m_s ^= m_s >> 12U;
        m_s ^= m_s << 25U;
        m_s ^= m_s >> 27U;
        const std::uint64_t r = m_s * 0x2545F4914F6CDD1DULL;
        return lo + (hi - lo) * (static_cast<float>(r >> 40U) / static_cast<float>(1U << 24U));
    }

private:
    std::uint64_t m_s;
};

}  // namespace

SyntheticScene makeSyntheticScene(std::size_t count, std::uint64_t seed, float coverage) {
    SyntheticScene scene;
    Rng rng(seed);
    constexpr float kMeanArea = 100.0F * 18.0F;
    const float area = static_cast<float>(count) * kMeanArea / (coverage > 0.0F ? coverage : 1.0F);
    const float height = std::sqrt(area * 9.0F / 16.0F);  // 16:9 screen
    scene.camera.viewport = {height * 16.0F / 9.0F, height};
    scene.camera.tilt_deg = 45.0F;
    scene.candidates.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        LabelCandidate c;
        c.id = 1000 + i * 7;  // sparse ids, not equal to indices
        c.priority = rng.uniform(0.0F, 1.0F);
        c.anchor = {rng.uniform(0.0F, scene.camera.viewport.x), rng.uniform(0.0F, scene.camera.viewport.y)};
        c.size = {rng.uniform(40.0F, 160.0F), rng.uniform(14.0F, 22.0F)};
        c.depth = rng.uniform(120.0F, 500.0F);
        const float k = rng.uniform(0.0F, 1.0F);
        if (k < 0.6F) {
            c.kind = LabelKind::Point;
        } else if (k < 0.7F) {
            c.kind = LabelKind::Area;
        } else if (k < 0.95F) {
            c.kind = LabelKind::Line;
            const float a = rng.uniform(-60.0F, 60.0F) * std::numbers::pi_v<float> / 180.0F;
            const float len = rng.uniform(80.0F, 300.0F);
            const glm::vec2 d{std::cos(a) * len * 0.5F, std::sin(a) * len * 0.5F};
            c.line_p0 = c.anchor - d;
            c.line_p1 = c.anchor + d;
        } else {
            c.kind = LabelKind::Circle;
        }
        scene.candidates.push_back(c);
    }
    return scene;
}

void wobbleScene(SyntheticScene& scene, std::uint64_t frame) {
    const float t = static_cast<float>(frame) * 0.05F;
    for (std::size_t i = 0; i < scene.candidates.size(); ++i) {
        const float phase = static_cast<float>(i % 97);
        const glm::vec2 d{0.6F * std::sin(t + phase), 0.6F * std::cos(1.3F * t + phase)};
        scene.candidates[i].anchor += d;
        scene.candidates[i].line_p0 += d;
        scene.candidates[i].line_p1 += d;
    }
}

void panScene(SyntheticScene& scene, glm::vec2 delta) {
    for (LabelCandidate& c : scene.candidates) {
        c.anchor += delta;
        c.line_p0 += delta;
        c.line_p1 += delta;
    }
}

void zoomRotateScene(SyntheticScene& scene, glm::vec2 center, float scale, float angle_rad) {
    const float c = std::cos(angle_rad) * scale;
    const float s = std::sin(angle_rad) * scale;
    const auto map = [&](glm::vec2 p) {
        const glm::vec2 d = p - center;
        return center + glm::vec2(c * d.x - s * d.y, s * d.x + c * d.y);
    };
    for (LabelCandidate& l : scene.candidates) {
        l.anchor = map(l.anchor);
        l.line_p0 = map(l.line_p0);
        l.line_p1 = map(l.line_p1);
    }
}

}  // namespace navmap::test
