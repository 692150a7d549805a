// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/guidance_symbol.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "navmap/map/turn_lanes.h"

namespace navmap::render {

namespace {

// Symbol units: the square [-1, 1]^2, y up.
constexpr float kStroke = 0.12f;    // half thickness of a path
constexpr float kHeadHalf = 0.32f;  // half width of the head's base
constexpr float kHeadLength = 0.4f;

class Builder {
public:
    Builder(glm::vec2 centre, float size_px) : m_centre(centre), m_half(0.5f * size_px) {}

    glm::vec2 px(glm::vec2 u) const { return m_centre + glm::vec2(u.x, -u.y) * m_half; }
    void triangle(std::vector<glm::vec2>& out, glm::vec2 a, glm::vec2 b, glm::vec2 c) const {
        out.insert(out.end(), {px(a), px(b), px(c)});
    }
    void disc(std::vector<glm::vec2>& out, glm::vec2 c, float r) const {
        constexpr int kSides = 16;
        for (int i = 0; i < kSides; ++i) {
            const float a0 = 2.0f * std::numbers::pi_v<float> * float(i) / kSides;
            const float a1 = 2.0f * std::numbers::pi_v<float> * float(i + 1) / kSides;
            triangle(out, c, c + r * glm::vec2(std::cos(a0), std::sin(a0)),
                     c + r * glm::vec2(std::cos(a1), std::sin(a1)));
        }
    }
    // A thick polyline, round joins, flat ends.
    void stroke(std::vector<glm::vec2>& out, const std::vector<glm::vec2>& path, float half = kStroke) const {
        for (std::size_t i = 0; i + 1 < path.size(); ++i) {
            const glm::vec2 a = path[i], b = path[i + 1];
            if (glm::length(b - a) < 1e-5f) continue;
            const glm::vec2 t = glm::normalize(b - a), n(-t.y, t.x);
            triangle(out, a + half * n, a - half * n, b + half * n);
            triangle(out, b + half * n, a - half * n, b - half * n);
            if (i > 0) disc(out, a, half);
        }
    }
    // The head: its base centred on `at`, pointing along `dir`.
    void head(std::vector<glm::vec2>& out, glm::vec2 at, glm::vec2 dir) const {
        const glm::vec2 t = glm::normalize(dir), n(-t.y, t.x);
        triangle(out, at + kHeadHalf * n, at - kHeadHalf * n, at + kHeadLength * t);
    }
    // A path with a head at its end, along its last piece.
    void arrow(std::vector<glm::vec2>& out, const std::vector<glm::vec2>& path) const {
        stroke(out, path);
        head(out, path.back(), path.back() - path[path.size() - 2]);
    }

private:
    glm::vec2 m_centre;
    float m_half;
};

// Points of a circular arc from angle a0 to a1 (degrees, counter-clockwise for a1 > a0).
std::vector<glm::vec2> arc(glm::vec2 c, float r, float a0, float a1) {
    const int n = std::max(2, static_cast<int>(std::abs(a1 - a0) / 10.0f) + 1);
    std::vector<glm::vec2> out;
    for (int i = 0; i <= n; ++i) {
        const float a = glm::radians(a0 + (a1 - a0) * float(i) / float(n));
        out.push_back(c + r * glm::vec2(std::cos(a), std::sin(a)));
    }
    return out;
}

std::vector<glm::vec2> operator+(std::vector<glm::vec2> a, const std::vector<glm::vec2>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

std::vector<glm::vec2> mirrored(std::vector<glm::vec2> path) {
    for (glm::vec2& p : path) p.x = -p.x;
    return path;
}

}  // namespace

GuidanceSymbolGeometry guidanceSymbol(ManeuverSymbol symbol, int roundabout_exit, glm::vec2 centre, float size_px) {
    GuidanceSymbolGeometry g;
    const Builder b(centre, size_px);
    using S = ManeuverSymbol;
    const std::vector<glm::vec2> straight = {{0.0f, -0.8f}, {0.0f, 0.45f}};
    const std::vector<glm::vec2> turn_right = std::vector<glm::vec2>{{-0.4f, -0.85f}} +
                                              arc({-0.1f, 0.0f}, 0.3f, 180.0f, 90.0f) +
                                              std::vector<glm::vec2>{{0.3f, 0.3f}};
    const std::vector<glm::vec2> slight_right = {{-0.2f, -0.85f}, {-0.2f, -0.15f}, {0.22f, 0.27f}};
    const std::vector<glm::vec2> sharp_right = {{-0.35f, -0.85f}, {-0.35f, 0.5f}, {0.12f, 0.03f}};
    const std::vector<glm::vec2> keep_right = {{0.0f, -0.85f}, {0.0f, -0.3f}, {0.35f, 0.05f}, {0.35f, 0.4f}};
    const std::vector<glm::vec2> keep_other = {{0.0f, -0.3f}, {0.0f, 0.8f}};
    switch (symbol) {
        case S::Straight: b.arrow(g.primary, straight); break;
        case S::Depart:
            b.arrow(g.primary, straight);
            b.disc(g.primary, straight.front(), 0.15f);  // where it starts
            break;
        case S::TurnRight: b.arrow(g.primary, turn_right); break;
        case S::TurnLeft: b.arrow(g.primary, mirrored(turn_right)); break;
        case S::SlightRight: b.arrow(g.primary, slight_right); break;
        case S::SlightLeft: b.arrow(g.primary, mirrored(slight_right)); break;
        case S::SharpRight: b.arrow(g.primary, sharp_right); break;
        case S::SharpLeft: b.arrow(g.primary, mirrored(sharp_right)); break;
        case S::UTurn:  // to the left (right-hand traffic)
            b.arrow(g.primary, std::vector<glm::vec2>{{0.35f, -0.85f}} + arc({0.0f, 0.15f}, 0.35f, 0.0f, 180.0f) +
                                   std::vector<glm::vec2>{{-0.35f, -0.15f}});
            break;
        case S::KeepRight:
        case S::Exit:
            b.stroke(g.secondary, keep_other);
            b.arrow(g.primary, keep_right);
            break;
        case S::KeepLeft:
            b.stroke(g.secondary, mirrored(keep_other));
            b.arrow(g.primary, mirrored(keep_right));
            break;
        case S::Merge:  // onto the road on the left
            b.stroke(g.secondary, {{0.0f, -0.85f}, {0.0f, -0.1f}});
            b.arrow(g.primary, {{0.4f, -0.85f}, {0.4f, -0.45f}, {0.0f, -0.1f}, {0.0f, 0.45f}});
            break;
        case S::Arrive: {
            b.stroke(g.primary, {{-0.4f, -0.9f}, {-0.4f, 0.85f}}, 0.07f);
            b.triangle(g.primary, {-0.4f, 0.85f}, {-0.4f, 0.25f}, {0.55f, 0.55f});
            break;
        }
        case S::Roundabout: {
            // Counter-clockwise from the entry at the bottom of the ring to the exit's arm.
            const glm::vec2 c(0.0f, 0.05f);
            constexpr float kR = 0.36f;
            b.stroke(g.secondary, arc(c, kR, 0.0f, 360.0f), 0.07f);
            const int k = std::max(roundabout_exit, 0);
            const float exit_deg = k == 0 ? 450.0f : k >= 4 ? 610.0f : 270.0f + 90.0f * float(k);
            const glm::vec2 out_dir(std::cos(glm::radians(exit_deg)), std::sin(glm::radians(exit_deg)));
            b.arrow(g.primary, std::vector<glm::vec2>{{0.0f, -0.9f}} + arc(c, kR, 270.0f, exit_deg) +
                                   std::vector<glm::vec2>{c + (kR + 0.15f) * out_dir});
            g.exit_label_at = b.px(c);
            g.exit_label_px = (kR - kStroke) * size_px;  // the ring's hole, across
            break;
        }
    }
    return g;
}

std::vector<glm::vec2> laneArrowSymbol(std::uint16_t arrows, glm::vec2 centre, float size_px) {
    namespace la = map::lane_arrow;
    std::vector<glm::vec2> out;
    if ((arrows & la::kKnown) == 0) return out;
    const Builder b(centre, size_px);
    const glm::vec2 base(0.0f, -0.9f), fork(0.0f, -0.15f);
    const bool merges = (arrows & (la::kMergeToLeft | la::kMergeToRight)) != 0;
    if ((arrows & ~(la::kMergeToLeft | la::kMergeToRight)) != 0) b.stroke(out, {base, fork});
    // A branch from the fork at `deg` from straight up (positive: to the right).
    const auto branch = [&](float deg, float length) {
        const float a = glm::radians(deg);
        b.arrow(out, {base, fork, fork + length * glm::vec2(std::sin(a), std::cos(a))});
    };
    if (arrows & la::kThrough) branch(0.0f, 0.6f);
    if (arrows & la::kSlightLeft) branch(-45.0f, 0.5f);
    if (arrows & la::kSlightRight) branch(45.0f, 0.5f);
    if (arrows & la::kLeft) branch(-90.0f, 0.4f);
    if (arrows & la::kRight) branch(90.0f, 0.4f);
    if (arrows & la::kSharpLeft) branch(-135.0f, 0.4f);
    if (arrows & la::kSharpRight) branch(135.0f, 0.4f);
    if (arrows & la::kReverse)  // back down on the left (right-hand traffic)
        b.arrow(out, std::vector<glm::vec2>{base, fork} + arc({-0.25f, fork.y}, 0.25f, 0.0f, 180.0f) +
                         std::vector<glm::vec2>{{-0.5f, -0.45f}});
    if (merges) {
        if (arrows & la::kMergeToLeft) b.arrow(out, {{0.3f, -0.9f}, {0.3f, -0.45f}, {-0.3f, 0.25f}, {-0.3f, 0.45f}});
        if (arrows & la::kMergeToRight) b.arrow(out, {{-0.3f, -0.9f}, {-0.3f, -0.45f}, {0.3f, 0.25f}, {0.3f, 0.45f}});
    }
    return out;
}

}  // namespace navmap::render
