// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/coastline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

namespace navmap::map {

namespace {

struct Chain {
    std::vector<PlanarPoint> points;
    std::vector<std::int64_t> ids;
    std::int64_t first_node = 0, last_node = 0;
    bool closed = false;
    bool dropped = false;
};

double distance(PlanarPoint a, PlanarPoint b) { return std::hypot(a.x - b.x, a.y - b.y); }

double borderDistance(PlanarPoint p, const Box& b) {
    return std::min(
        {std::abs(p.x - b.min_x), std::abs(b.max_x - p.x), std::abs(p.y - b.min_y), std::abs(b.max_y - p.y)});
}

std::string idList(const std::vector<std::int64_t>& ids) {
    std::string s;
    for (std::size_t i = 0; i < ids.size() && i < 8; ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
    if (ids.size() > 8) s += ", ... (" + std::to_string(ids.size()) + " ways)";
    return s;
}

std::string metres(double m) { return std::to_string(static_cast<long>(std::lround(m))) + " m"; }

/// The box's border as one line, parameter t counter-clockwise from the south-west corner.
class Border {
public:
    explicit Border(const Box& b) : m_b(b), m_w(b.max_x - b.min_x), m_h(b.max_y - b.min_y) {}
    [[nodiscard]] double perimeter() const { return 2 * (m_w + m_h); }
    /// The nearest point on the border.
    [[nodiscard]] PlanarPoint snap(PlanarPoint p) const {
        const double x = std::clamp(p.x, m_b.min_x, m_b.max_x), y = std::clamp(p.y, m_b.min_y, m_b.max_y);
        const std::array<double, 4> d{y - m_b.min_y, m_b.max_x - x, m_b.max_y - y, x - m_b.min_x};
        switch (std::min_element(d.begin(), d.end()) - d.begin()) {
            case 0: return {x, m_b.min_y};
            case 1: return {m_b.max_x, y};
            case 2: return {x, m_b.max_y};
            default: return {m_b.min_x, y};
        }
    }
    /// t of a point on the border.
    [[nodiscard]] double param(PlanarPoint p) const {
        const std::array<double, 4> d{std::abs(p.y - m_b.min_y), std::abs(m_b.max_x - p.x), std::abs(m_b.max_y - p.y),
                                      std::abs(p.x - m_b.min_x)};
        switch (std::min_element(d.begin(), d.end()) - d.begin()) {
            case 0: return p.x - m_b.min_x;
            case 1: return m_w + (p.y - m_b.min_y);
            case 2: return m_w + m_h + (m_b.max_x - p.x);
            default: return 2 * m_w + m_h + (m_b.max_y - p.y);
        }
    }
    /// Distance going clockwise (decreasing t) from `from` to `to`, in [0, perimeter).
    [[nodiscard]] double clockwise(double from, double to) const {
        double d = std::fmod(from - to, perimeter());
        if (d < 0) d += perimeter();
        return d;
    }
    /// The corners passed going clockwise from t `from` over `length`, in that order.
    void cornersBetween(double from, double length, std::vector<PlanarPoint>& out) const {
        const std::array<std::pair<double, PlanarPoint>, 4> corners{
            std::pair{0.0, PlanarPoint{m_b.min_x, m_b.min_y}}, std::pair{m_w, PlanarPoint{m_b.max_x, m_b.min_y}},
            std::pair{m_w + m_h, PlanarPoint{m_b.max_x, m_b.max_y}},
            std::pair{2 * m_w + m_h, PlanarPoint{m_b.min_x, m_b.max_y}}};
        std::vector<std::pair<double, PlanarPoint>> passed;
        for (const auto& [t, p] : corners) {
            const double d = clockwise(from, t);
            if (d > 0 && d < length) passed.emplace_back(d, p);
        }
        std::sort(passed.begin(), passed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (const auto& c : passed) out.push_back(c.second);
    }

private:
    Box m_b;
    double m_w, m_h;
};

/// Joins ways that share end nodes (a way's last node is the next one's first) into chains.
std::vector<Chain> joinWays(std::vector<CoastWay>& ways) {
    std::unordered_multimap<std::int64_t, std::size_t> by_first;
    std::unordered_map<std::int64_t, int> ends_at;  // how many ways end at a node
    for (std::size_t i = 0; i < ways.size(); ++i) {
        by_first.emplace(ways[i].first_node, i);
        ++ends_at[ways[i].last_node];
    }
    std::vector<char> used(ways.size(), 0);
    std::vector<Chain> chains;
    auto grow = [&](std::size_t start) {
        Chain c;
        c.first_node = ways[start].first_node;
        std::size_t i = start;
        for (;;) {
            used[i] = 1;
            auto& pts = ways[i].points;
            c.points.insert(c.points.end(), pts.begin() + (c.points.empty() ? 0 : 1), pts.end());
            c.ids.push_back(ways[i].id);
            c.last_node = ways[i].last_node;
            if (c.last_node == c.first_node) {
                c.closed = true;
                break;
            }
            auto [lo, hi] = by_first.equal_range(c.last_node);
            auto next = std::find_if(lo, hi, [&](const auto& kv) { return !used[kv.second]; });
            if (next == hi) break;
            i = next->second;
        }
        chains.push_back(std::move(c));
    };
    // Chain heads first (no way ends where they start), then what is left: rings.
    for (std::size_t i = 0; i < ways.size(); ++i) {
        if (!used[i] && ends_at.find(ways[i].first_node) == ends_at.end()) grow(i);
    }
    for (std::size_t i = 0; i < ways.size(); ++i) {
        if (!used[i]) grow(i);
    }
    return chains;
}

}  // namespace

Coast assembleCoast(std::vector<CoastWay> ways, const Box& box, double close_m) {
    Coast coast;
    std::erase_if(ways, [](const CoastWay& w) { return w.points.size() < 2; });
    if (ways.empty()) return coast;
    std::vector<Chain> chains = joinWays(ways);

    // Gap closing: an open end in the interior is joined to the nearest open start within
    // close_m (its own start closes it into a ring).
    auto interior = [&](PlanarPoint p) { return borderDistance(p, box) > close_m; };
    for (bool joined = true; joined;) {
        joined = false;
        for (std::size_t i = 0; i < chains.size() && !joined; ++i) {
            Chain& a = chains[i];
            if (a.closed || a.dropped || !interior(a.points.back())) continue;
            std::size_t best = chains.size();
            double best_d = close_m;
            for (std::size_t j = 0; j < chains.size(); ++j) {
                const Chain& b = chains[j];
                if (b.closed || b.dropped) continue;
                const double d = distance(a.points.back(), b.points.front());
                if (d <= best_d) {
                    best_d = d;
                    best = j;
                }
            }
            if (best == chains.size()) continue;
            ++coast.gaps_closed;
            coast.warnings.push_back("coastline gap of " + metres(best_d) + " closed after way " +
                                     std::to_string(a.ids.back()) + " (to way " +
                                     std::to_string(chains[best].ids.front()) + ")");
            if (best == i) {
                a.closed = true;
            } else {
                Chain& b = chains[best];
                a.points.insert(a.points.end(), b.points.begin(), b.points.end());
                a.ids.insert(a.ids.end(), b.ids.begin(), b.ids.end());
                a.last_node = b.last_node;
                b.dropped = true;
                b.points.clear();
            }
            joined = true;
        }
    }

    // Open chains reach the border at both ends or are broken.
    const Border border(box);
    struct Open {
        std::vector<PlanarPoint> points;
        double t_in = 0, t_out = 0;
    };
    std::vector<Open> open;
    for (Chain& c : chains) {
        if (c.dropped) continue;
        if (c.closed) {
            if (c.points.size() > 1 && distance(c.points.front(), c.points.back()) == 0.0) c.points.pop_back();
            if (c.points.size() < 3) continue;
            const double a = ringSignedArea(c.points);
            if (a > 0) {  // land on the left, counter-clockwise: an island
                std::reverse(c.points.begin(), c.points.end());
                coast.islands.push_back(std::move(c.points));
            } else if (a < 0) {  // water enclosed by land
                std::reverse(c.points.begin(), c.points.end());
                coast.sea.push_back(std::move(c.points));
            }
            continue;
        }
        if (interior(c.points.front()) || interior(c.points.back())) {
            coast.ways_left_out += c.ids.size();
            const PlanarPoint p = interior(c.points.back()) ? c.points.back() : c.points.front();
            coast.warnings.push_back("broken coastline: ways " + idList(c.ids) + " end " +
                                     metres(borderDistance(p, box)) +
                                     " inside the data's bounds with no coastline within " + metres(close_m) +
                                     "; left out of the land/sea split (drawn as land)");
            continue;
        }
        Open o;
        const PlanarPoint in = border.snap(c.points.front()), out = border.snap(c.points.back());
        if (distance(in, c.points.front()) > 0) o.points.push_back(in);
        o.points.insert(o.points.end(), c.points.begin(), c.points.end());
        if (distance(out, c.points.back()) > 0) o.points.push_back(out);
        o.t_in = border.param(in);
        o.t_out = border.param(out);
        open.push_back(std::move(o));
    }

    // Round the border clockwise (water on the right) from each exit to the next entry.
    std::vector<char> used(open.size(), 0);
    for (std::size_t i = 0; i < open.size(); ++i) {
        if (used[i]) continue;
        std::vector<PlanarPoint> ring;
        std::size_t j = i;
        for (std::size_t guard = 0; guard <= open.size(); ++guard) {
            used[j] = 1;
            ring.insert(ring.end(), open[j].points.begin(), open[j].points.end());
            std::size_t next = i;
            double best = std::numeric_limits<double>::infinity();
            for (std::size_t k = 0; k < open.size(); ++k) {
                if (used[k] && k != i) continue;
                const double d = border.clockwise(open[j].t_out, open[k].t_in);
                if (d < best) {
                    best = d;
                    next = k;
                }
            }
            border.cornersBetween(open[j].t_out, best, ring);
            if (next == i) break;
            j = next;
        }
        if (ring.size() < 3) continue;
        std::reverse(ring.begin(), ring.end());  // clockwise around the water -> counter-clockwise
        coast.sea.push_back(std::move(ring));
    }
    // Islands and no coastline across the data's bounds: the sea is all around them.
    if (open.empty() && !coast.islands.empty()) {
        coast.sea.push_back(
            {{box.min_x, box.min_y}, {box.max_x, box.min_y}, {box.max_x, box.max_y}, {box.min_x, box.max_y}});
    }
    if (coast.sea.empty()) coast.islands.clear();
    return coast;
}

std::vector<char> samplesInside(const std::vector<std::vector<PlanarPoint>>& rings, double x0, double y0,
                                double spacing, int n) {
    std::vector<char> inside(static_cast<std::size_t>(n) * n, 0);
    std::vector<double> xs;
    // Border rows are tested a hair inside the grid, and border columns filled a hair beyond
    // the crossings: rings clipped to a tile run along its border, and the samples there (shared
    // with the neighbour tile) must come out as they do on the neighbour's side.
    const double e = 1e-6 * spacing;
    for (int r = 0; r < n; ++r) {
        double y = y0 + r * spacing;
        if (n > 1) y = std::clamp(y, y0 + e, y0 + (n - 1) * spacing - e);
        xs.clear();
        for (const auto& ring : rings) {
            for (std::size_t i = 0; i < ring.size(); ++i) {
                const PlanarPoint a = ring[i], b = ring[(i + 1) % ring.size()];
                if ((a.y > y) == (b.y > y)) continue;  // half-open: each crossing counted once
                xs.push_back(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
            }
        }
        std::sort(xs.begin(), xs.end());
        for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
            const int c0 = std::max(0, static_cast<int>(std::ceil((xs[k] - e - x0) / spacing)));
            const int c1 = std::min(n - 1, static_cast<int>(std::floor((xs[k + 1] + e - x0) / spacing)));
            for (int c = c0; c <= c1; ++c) inside[static_cast<std::size_t>(r) * n + c] = 1;
        }
    }
    return inside;
}

}  // namespace navmap::map
