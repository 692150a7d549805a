// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

namespace navmap::map {

Box boundsOf(std::span<const PlanarPoint> points) {
    Box b{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
          std::numeric_limits<double>::lowest()};
    for (const auto& p : points) {
        b.min_x = std::min(b.min_x, p.x);
        b.min_y = std::min(b.min_y, p.y);
        b.max_x = std::max(b.max_x, p.x);
        b.max_y = std::max(b.max_y, p.y);
    }
    return b;
}

double ringSignedArea(std::span<const PlanarPoint> ring) {
    if (ring.size() < 3) return 0.0;
    // Shoelace relative to the first point for precision far from the origin.
    const PlanarPoint o = ring[0];
    double twice = 0.0;
    for (std::size_t i = 1; i + 1 < ring.size(); ++i) {
        const double ax = ring[i].x - o.x, ay = ring[i].y - o.y;
        const double bx = ring[i + 1].x - o.x, by = ring[i + 1].y - o.y;
        twice += ax * by - bx * ay;
    }
    return 0.5 * twice;
}

namespace {

/// Area-weighted centroid contribution of one ring (absolute area, centroid).
std::pair<double, PlanarPoint> ringCentroid(const std::vector<PlanarPoint>& ring) {
    if (ring.size() < 3) return {0.0, {}};
    const PlanarPoint o = ring[0];
    double a2 = 0, cx = 0, cy = 0;
    for (std::size_t i = 0; i < ring.size(); ++i) {
        const PlanarPoint& p = ring[i];
        const PlanarPoint& q = ring[(i + 1) % ring.size()];
        const double px = p.x - o.x, py = p.y - o.y, qx = q.x - o.x, qy = q.y - o.y;
        const double cross = px * qy - qx * py;
        a2 += cross;
        cx += (px + qx) * cross;
        cy += (py + qy) * cross;
    }
    if (a2 == 0.0) return {0.0, {}};
    return {std::abs(a2) * 0.5, {o.x + cx / (3.0 * a2), o.y + cy / (3.0 * a2)}};
}

}  // namespace

PlanarPoint polygonBarycenter(std::span<const std::vector<PlanarPoint>> outers,
                              std::span<const std::vector<PlanarPoint>> inners) {
    double area = 0, sx = 0, sy = 0;
    auto add = [&](const std::vector<PlanarPoint>& ring, double sign) {
        const auto [a, c] = ringCentroid(ring);
        area += sign * a;
        sx += sign * a * c.x;
        sy += sign * a * c.y;
    };
    for (const auto& r : outers) add(r, 1.0);
    for (const auto& r : inners) add(r, -1.0);
    if (area > 1e-9) return {sx / area, sy / area};
    double mx = 0, my = 0;
    std::size_t n = 0;
    for (const auto& r : outers) {
        for (const auto& p : r) {
            mx += p.x;
            my += p.y;
            ++n;
        }
    }
    return n ? PlanarPoint{mx / n, my / n} : PlanarPoint{};
}

double polylineLength(std::span<const PlanarPoint> line) {
    double len = 0;
    for (std::size_t i = 1; i < line.size(); ++i)
        len += std::hypot(line[i].x - line[i - 1].x, line[i].y - line[i - 1].y);
    return len;
}

PlanarPoint polylineCenter(std::span<const PlanarPoint> line) {
    if (line.empty()) return {};
    const double half = polylineLength(line) * 0.5;
    double acc = 0;
    for (std::size_t i = 1; i < line.size(); ++i) {
        const double seg = std::hypot(line[i].x - line[i - 1].x, line[i].y - line[i - 1].y);
        if (acc + seg >= half && seg > 0) {
            const double t = (half - acc) / seg;
            return {line[i - 1].x + t * (line[i].x - line[i - 1].x), line[i - 1].y + t * (line[i].y - line[i - 1].y)};
        }
        acc += seg;
    }
    return line.back();
}

Segment longestStraightSegment(std::span<const PlanarPoint> line, double max_turn_deg) {
    if (line.size() < 2) return line.empty() ? Segment{} : Segment{line[0], line[0]};
    const double max_turn = max_turn_deg * std::numbers::pi / 180.0;
    Segment best{line[0], line[1]};
    double best_len = -1;
    std::size_t start = 0;
    while (start + 1 < line.size()) {
        const double dir = std::atan2(line[start + 1].y - line[start].y, line[start + 1].x - line[start].x);
        std::size_t end = start + 1;
        while (end + 1 < line.size()) {
            const double d = std::atan2(line[end + 1].y - line[end].y, line[end + 1].x - line[end].x);
            double turn = std::abs(d - dir);
            if (turn > std::numbers::pi) turn = 2 * std::numbers::pi - turn;
            if (turn > max_turn) break;
            ++end;
        }
        const double len = std::hypot(line[end].x - line[start].x, line[end].y - line[start].y);
        if (len > best_len) {
            best_len = len;
            best = {line[start], line[end]};
        }
        start = end;
    }
    return best;
}

double segmentDistance(PlanarPoint p, PlanarPoint a, PlanarPoint b) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

namespace {}  // namespace

std::vector<PlanarPoint> simplifyPolyline(std::span<const PlanarPoint> line, double tolerance) {
    const std::vector<char> keep = douglasPeucker(
        line.size(), tolerance,
        [&](std::size_t k, std::size_t i, std::size_t j) { return segmentDistance(line[k], line[i], line[j]); });
    std::vector<PlanarPoint> out;
    for (std::size_t k = 0; k < line.size(); ++k) {
        if (keep[k]) out.push_back(line[k]);
    }
    return out;
}

std::vector<PlanarPoint> simplifyRing(std::span<const PlanarPoint> ring, double tolerance) {
    if (ring.size() <= 3 || tolerance <= 0) return {ring.begin(), ring.end()};
    // Split at the point farthest from the first so both halves are proper polylines.
    std::size_t far = 0;
    double far_d = -1;
    for (std::size_t k = 1; k < ring.size(); ++k) {
        const double d = std::hypot(ring[k].x - ring[0].x, ring[k].y - ring[0].y);
        if (d > far_d) {
            far_d = d;
            far = k;
        }
    }
    std::vector<PlanarPoint> first(ring.begin(), ring.begin() + static_cast<std::ptrdiff_t>(far) + 1);
    std::vector<PlanarPoint> second(ring.begin() + static_cast<std::ptrdiff_t>(far), ring.end());
    second.push_back(ring[0]);
    auto a = simplifyPolyline(first, tolerance);
    auto b = simplifyPolyline(second, tolerance);
    a.pop_back();                               // far point repeats as b's first
    a.insert(a.end(), b.begin(), b.end() - 1);  // b's last is ring[0]
    return a;
}

std::vector<std::vector<PlanarPoint>> clipPolyline(std::span<const PlanarPoint> line, const Box& box) {
    std::vector<std::vector<PlanarPoint>> pieces;
    std::vector<PlanarPoint> current;
    auto flush = [&] {
        if (current.size() >= 2) pieces.push_back(std::move(current));
        current.clear();
    };
    for (std::size_t i = 1; i < line.size(); ++i) {
        const PlanarPoint a = line[i - 1], b = line[i];
        const double dx = b.x - a.x, dy = b.y - a.y;
        double t0 = 0, t1 = 1;
        bool inside = true;
        const double p[4] = {-dx, dx, -dy, dy};
        const double q[4] = {a.x - box.min_x, box.max_x - a.x, a.y - box.min_y, box.max_y - a.y};
        for (int k = 0; k < 4 && inside; ++k) {
            if (p[k] == 0) {
                if (q[k] < 0) inside = false;
            } else {
                const double t = q[k] / p[k];
                if (p[k] < 0)
                    t0 = std::max(t0, t);
                else
                    t1 = std::min(t1, t);
                if (t0 > t1) inside = false;
            }
        }
        if (!inside) {
            flush();
            continue;
        }
        const PlanarPoint ca{a.x + t0 * dx, a.y + t0 * dy};
        const PlanarPoint cb{a.x + t1 * dx, a.y + t1 * dy};
        if (current.empty() || t0 > 0) {
            flush();
            current.push_back(ca);
        }
        current.push_back(cb);
        if (t1 < 1) flush();
    }
    flush();
    return pieces;
}

std::vector<PlanarPoint> clipRing(std::span<const PlanarPoint> ring, const Box& box) {
    std::vector<PlanarPoint> in(ring.begin(), ring.end());
    std::vector<PlanarPoint> out;
    for (int edge = 0; edge < 4 && !in.empty(); ++edge) {
        auto inside = [&](PlanarPoint p) {
            switch (edge) {
                case 0: return p.x >= box.min_x;
                case 1: return p.x <= box.max_x;
                case 2: return p.y >= box.min_y;
                default: return p.y <= box.max_y;
            }
        };
        auto cut = [&](PlanarPoint a, PlanarPoint b) {
            double t = 0;
            switch (edge) {
                case 0: t = (box.min_x - a.x) / (b.x - a.x); break;
                case 1: t = (box.max_x - a.x) / (b.x - a.x); break;
                case 2: t = (box.min_y - a.y) / (b.y - a.y); break;
                default: t = (box.max_y - a.y) / (b.y - a.y); break;
            }
            PlanarPoint p{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
            // Snap exactly onto the edge so neighbouring tiles share coordinates.
            if (edge == 0)
                p.x = box.min_x;
            else if (edge == 1)
                p.x = box.max_x;
            else if (edge == 2)
                p.y = box.min_y;
            else
                p.y = box.max_y;
            return p;
        };
        out.clear();
        for (std::size_t i = 0; i < in.size(); ++i) {
            const PlanarPoint cur = in[i];
            const PlanarPoint prev = in[(i + in.size() - 1) % in.size()];
            const bool ci = inside(cur), pi = inside(prev);
            if (ci) {
                if (!pi) out.push_back(cut(prev, cur));
                out.push_back(cur);
            } else if (pi) {
                out.push_back(cut(prev, cur));
            }
        }
        std::swap(in, out);
    }
    if (in.size() < 3) in.clear();
    return in;
}

}  // namespace navmap::map
