// SPDX-License-Identifier: Apache-2.0
#include "tile_selection.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace navmap::map {

namespace {

bool pointInPolygon(PlanarPoint p, std::span<const PlanarPoint> poly) {
    bool inside = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        if ((poly[i].y > p.y) != (poly[j].y > p.y) &&
            p.x < (poly[j].x - poly[i].x) * (p.y - poly[i].y) / (poly[j].y - poly[i].y) + poly[i].x) {
            inside = !inside;
        }
    }
    return inside;
}

float priorityFor(const TileScheme& s, TileId id, PlanarPoint focus, float base) {
    const Box b = s.bounds(id);
    const double cx = 0.5 * (b.min_x + b.max_x), cy = 0.5 * (b.min_y + b.max_y);
    return base - static_cast<float>(std::hypot(cx - focus.x, cy - focus.y) / s.tileSize(id.level));
}

}  // namespace

std::vector<TileRequest> tilesInPolygon(const TileScheme& s, int level, std::span<const PlanarPoint> polygon,
                                        PlanarPoint focus, float base) {
    std::vector<TileRequest> out;
    if (polygon.size() < 3) return out;
    const TileRange r = s.range(level, boundsOf(polygon));
    if (r.empty) return out;
    std::vector<PlanarPoint> closed(polygon.begin(), polygon.end());
    closed.push_back(polygon.front());
    for (std::uint32_t y = r.y0; y <= r.y1; ++y) {
        for (std::uint32_t x = r.x0; x <= r.x1; ++x) {
            const TileId id{static_cast<std::uint8_t>(level), x, y};
            const Box b = s.bounds(id);
            const PlanarPoint center{0.5 * (b.min_x + b.max_x), 0.5 * (b.min_y + b.max_y)};
            if (pointInPolygon(center, polygon) || !clipPolyline(closed, b).empty()) {
                out.push_back({id, priorityFor(s, id, focus, base)});
            }
        }
    }
    return out;
}

std::vector<TileRequest> tilesInCircle(const TileScheme& s, int level, PlanarPoint c, double radius, float base) {
    std::vector<TileRequest> out;
    const TileRange r = s.range(level, {c.x - radius, c.y - radius, c.x + radius, c.y + radius});
    if (r.empty) return out;
    for (std::uint32_t y = r.y0; y <= r.y1; ++y) {
        for (std::uint32_t x = r.x0; x <= r.x1; ++x) {
            const TileId id{static_cast<std::uint8_t>(level), x, y};
            const Box b = s.bounds(id);
            const double dx = std::max({b.min_x - c.x, 0.0, c.x - b.max_x});
            const double dy = std::max({b.min_y - c.y, 0.0, c.y - b.max_y});
            if (dx * dx + dy * dy <= radius * radius) out.push_back({id, priorityFor(s, id, c, base)});
        }
    }
    return out;
}

std::vector<TileRequest> tilesAlongPolyline(const TileScheme& s, int level, std::span<const PlanarPoint> line,
                                            double radius, double length_m, float base) {
    std::vector<TileRequest> out;
    if (line.empty()) return out;
    const double step = std::max(1.0, s.tileSize(level) * 0.5);
    double travelled = 0;
    auto visit = [&](PlanarPoint p) {
        for (auto req : tilesInCircle(s, level, p, radius, base)) {
            req.priority = base - static_cast<float>(travelled / s.tileSize(level));
            out.push_back(req);
        }
    };
    visit(line.front());
    for (std::size_t i = 1; i < line.size() && travelled < length_m; ++i) {
        const double dx = line[i].x - line[i - 1].x, dy = line[i].y - line[i - 1].y;
        const double len = std::hypot(dx, dy);
        for (double t = step; t <= len && travelled + t <= length_m; t += step) {
            const double saved = travelled;
            travelled += t;
            visit({line[i - 1].x + dx * t / len, line[i - 1].y + dy * t / len});
            travelled = saved;
        }
        travelled += len;
        if (travelled <= length_m) visit(line[i]);
    }
    return mergeRequests(std::move(out), {});
}

std::vector<TileRequest> mergeRequests(std::vector<TileRequest> a, std::span<const TileRequest> b) {
    a.insert(a.end(), b.begin(), b.end());
    std::unordered_map<std::uint64_t, std::size_t> best;
    std::vector<TileRequest> out;
    for (const auto& r : a) {
        auto [it, inserted] = best.emplace(r.id.key(), out.size());
        if (inserted)
            out.push_back(r);
        else
            out[it->second].priority = std::max(out[it->second].priority, r.priority);
    }
    std::sort(out.begin(), out.end(),
              [](const TileRequest& x, const TileRequest& y) { return x.priority > y.priority; });
    return out;
}

std::vector<TileRequest> selectTiles(const TileScheme& s, int level, const CameraFootprint& cam) {
    constexpr float kVisible = 2000.0f;
    constexpr float kPrefetch = 999.0f;
    auto visible = tilesInPolygon(s, level, cam.ground, cam.position, kVisible);
    for (auto& r : visible) r.priority = std::max(r.priority, 1000.0f);
    if (cam.prefetch_m <= 0) return mergeRequests(std::move(visible), {});
    std::vector<TileRequest> ahead;
    const double radius = s.tileSize(level) * 0.75;
    if (!cam.route.empty()) {
        ahead = tilesAlongPolyline(s, level, cam.route, radius, cam.prefetch_m, kPrefetch);
    } else {
        const double h = cam.heading_deg * std::numbers::pi / 180.0;
        const PlanarPoint line[2] = {
            cam.position,
            {cam.position.x + std::sin(h) * cam.prefetch_m, cam.position.y + std::cos(h) * cam.prefetch_m}};
        ahead = tilesAlongPolyline(s, level, line, radius, cam.prefetch_m, kPrefetch);
    }
    for (auto& r : ahead) r.priority = std::min(r.priority, kPrefetch);
    return mergeRequests(std::move(visible), ahead);
}

}  // namespace navmap::map
