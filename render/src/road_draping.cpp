// SPDX-License-Identifier: Apache-2.0
#include "road_draping.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace navmap::render {

namespace {

// A triangle of the grid: cell (row, col), half 0 = south-east triangle
// (SW, SE, NE), half 1 = north-west triangle (SW, NE, NW).
struct Tri {
    int row, col, half;
};

std::array<glm::dvec2, 3> corners(const HeightGrid& g, const Tri& t) {
    const double x0 = t.col * g.spacing, x1 = (t.col + 1) * g.spacing;
    const double y0 = t.row * g.spacing, y1 = (t.row + 1) * g.spacing;
    if (t.half == 0) return {glm::dvec2{x0, y0}, glm::dvec2{x1, y0}, glm::dvec2{x1, y1}};
    return {glm::dvec2{x0, y0}, glm::dvec2{x1, y1}, glm::dvec2{x0, y1}};
}

std::array<double, 3> cornerHeights(const HeightGrid& g, const Tri& t) {
    if (t.half == 0) return {g.at(t.row, t.col), g.at(t.row, t.col + 1), g.at(t.row + 1, t.col + 1)};
    return {g.at(t.row, t.col), g.at(t.row + 1, t.col + 1), g.at(t.row + 1, t.col)};
}

// Neighbour across the edge opposite vertex i (nullopt-like: row -1 means outside).
Tri neighbour(const Tri& t, int i) {
    if (t.half == 0) {
        switch (i) {
            case 0: return {t.row, t.col + 1, 1};   // east edge
            case 1: return {t.row, t.col, 1};       // diagonal
            default: return {t.row - 1, t.col, 1};  // south edge
        }
    }
    switch (i) {
        case 0: return {t.row + 1, t.col, 0};  // north edge
        case 1: return {t.row, t.col - 1, 0};  // west edge
        default: return {t.row, t.col, 0};     // diagonal
    }
}

bool inside(const HeightGrid& g, const Tri& t) {
    return t.row >= 0 && t.col >= 0 && t.row < g.size - 1 && t.col < g.size - 1;
}

Tri locate(const HeightGrid& g, glm::dvec2 p) {
    const int cells = g.size - 1;
    const int col = std::clamp(static_cast<int>(std::floor(p.x / g.spacing)), 0, cells - 1);
    const int row = std::clamp(static_cast<int>(std::floor(p.y / g.spacing)), 0, cells - 1);
    const double fx = p.x / g.spacing - col, fy = p.y / g.spacing - row;
    return {row, col, fy > fx ? 1 : 0};
}

// Barycentric coordinates of p and their gradients (constant per triangle).
struct Bary {
    std::array<double, 3> lambda;
    std::array<glm::dvec2, 3> gradient;
};

Bary barycentric(const std::array<glm::dvec2, 3>& c, glm::dvec2 p) {
    const glm::dvec2 e0 = c[1] - c[0], e1 = c[2] - c[0];
    const double det = e0.x * e1.y - e0.y * e1.x;
    Bary b;
    // lambda1 = cross(p - c0, e1) / cross(e0, e1) etc., written with gradients so that
    // d(lambda_i)/ds along v is gradient_i . v (seed 3.6.1: a_i / d_i).
    b.gradient[1] = glm::dvec2(e1.y, -e1.x) / det;
    b.gradient[2] = glm::dvec2(-e0.y, e0.x) / det;
    b.gradient[0] = -b.gradient[1] - b.gradient[2];
    const glm::dvec2 d = p - c[0];
    b.lambda[1] = glm::dot(b.gradient[1], d);
    b.lambda[2] = glm::dot(b.gradient[2], d);
    b.lambda[0] = 1.0 - b.lambda[1] - b.lambda[2];
    return b;
}

}  // namespace

double HeightGrid::heightAt(double x, double y) const {
    const glm::dvec2 p{std::clamp(x, 0.0, extent()), std::clamp(y, 0.0, extent())};
    const Tri t = locate(*this, p);
    const Bary b = barycentric(corners(*this, t), p);
    const auto h = cornerHeights(*this, t);
    return b.lambda[0] * h[0] + b.lambda[1] * h[1] + b.lambda[2] * h[2];
}

std::vector<std::uint32_t> gridTriangleIndices(int size) {
    std::vector<std::uint32_t> indices;
    indices.reserve(static_cast<std::size_t>(size - 1) * (size - 1) * 6);
    for (int r = 0; r + 1 < size; ++r) {
        for (int c = 0; c + 1 < size; ++c) {
            const auto sw = static_cast<std::uint32_t>(r * size + c);
            const auto se = sw + 1;
            const auto nw = static_cast<std::uint32_t>((r + 1) * size + c);
            const auto ne = nw + 1;
            indices.insert(indices.end(), {sw, se, ne, sw, ne, nw});
        }
    }
    return indices;
}

std::vector<glm::dvec3> drapePolyline(const HeightGrid& grid, std::span<const glm::dvec2> polyline) {
    std::vector<glm::dvec3> out;
    if (polyline.empty() || grid.size < 2) return out;
    const double ext = grid.extent();
    auto clamp_point = [&](glm::dvec2 p) { return glm::dvec2{std::clamp(p.x, 0.0, ext), std::clamp(p.y, 0.0, ext)}; };
    const double eps = grid.spacing * 1e-9;
    auto emit = [&](glm::dvec2 p, double h) {
        if (!out.empty() && std::abs(out.back().x - p.x) <= eps && std::abs(out.back().y - p.y) <= eps) return;
        out.emplace_back(p.x, p.y, h);
    };

    glm::dvec2 p = clamp_point(polyline[0]);
    emit(p, grid.heightAt(p.x, p.y));
    for (std::size_t i = 1; i < polyline.size(); ++i) {
        const glm::dvec2 target = clamp_point(polyline[i]);
        const double length = glm::length(target - p);
        if (length <= eps) continue;
        const glm::dvec2 v = (target - p) / length;
        Tri tri = locate(grid, p);
        double travelled = 0.0;
        // Every crossing moves into a new triangle; a segment cannot cross more triangles than
        // about three per cell it passes, plus the fan around a vertex it starts on.
        const int guard = 8 + 4 * static_cast<int>(length / grid.spacing + 2.0) * 3;
        for (int step = 0; step < guard; ++step) {
            const Bary b = barycentric(corners(grid, tri), p);
            // seed 3.6.1: per edge, the distance along v until lambda_i reaches 0; only edges we
            // move towards (gradient . v < 0) count; the smallest one is the exit.
            double exit = std::numeric_limits<double>::infinity();
            int exit_edge = -1;
            for (int k = 0; k < 3; ++k) {
                const double rate = glm::dot(b.gradient[k], v);
                if (rate >= -1e-15) continue;
                const double x = std::max(0.0, b.lambda[k]) / -rate;
                if (x < exit) {
                    exit = x;
                    exit_edge = k;
                }
            }
            const double remaining = length - travelled;
            if (exit_edge < 0 || exit >= remaining) break;  // target lies in this triangle
            const Tri next = neighbour(tri, exit_edge);
            if (!inside(grid, next)) break;  // leaving the grid: finish in this triangle
            travelled += exit;
            p += v * exit;
            const auto h = cornerHeights(grid, tri);
            const Bary at = barycentric(corners(grid, tri), p);
            emit(p, at.lambda[0] * h[0] + at.lambda[1] * h[1] + at.lambda[2] * h[2]);
            tri = next;
        }
        p = target;
        emit(p, grid.heightAt(p.x, p.y));
    }
    return out;
}

std::vector<glm::dvec3> mergeDrapedPieces(std::span<const glm::dvec3> draped, double max_height_error_m) {
    constexpr double kPlanarTolerance = 0.01;  // metres off the 2D chord
    std::vector<glm::dvec3> out;
    if (draped.empty()) return out;
    out.push_back(draped.front());
    std::size_t anchor = 0;
    // Can the chord anchor -> end replace every vertex strictly between them?
    auto chord_holds = [&](std::size_t end) {
        const glm::dvec3 a = draped[anchor], b = draped[end];
        const glm::dvec2 d = glm::dvec2(b) - glm::dvec2(a);
        const double len2 = glm::dot(d, d);
        if (len2 <= 0.0) return false;
        for (std::size_t j = anchor + 1; j < end; ++j) {
            const glm::dvec2 v = glm::dvec2(draped[j]) - glm::dvec2(a);
            const double t = glm::dot(v, d) / len2;
            if (t <= 0.0 || t >= 1.0) return false;
            const double off = std::abs(v.x * d.y - v.y * d.x) / std::sqrt(len2);
            if (off > kPlanarTolerance) return false;
            if (std::abs(a.z + t * (b.z - a.z) - draped[j].z) > max_height_error_m) return false;
        }
        return true;
    };
    for (std::size_t i = 2; i < draped.size(); ++i) {
        if (!chord_holds(i)) {
            out.push_back(draped[i - 1]);
            anchor = i - 1;
        }
    }
    if (draped.size() > 1) out.push_back(draped.back());
    return out;
}

}  // namespace navmap::render
