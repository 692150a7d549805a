// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/triangulator.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <queue>

namespace navmap::map {

namespace {

// CGAL's constrained Delaunay triangulation (libcgal-dev, header-only) with exact predicates:
// crossing constraints (self-intersecting OSM rings) are split at a computed intersection
// point instead of failing. The "plus" hierarchy counts how many input edges run along each
// triangulation edge, which the odd winding rule needs (see markInside).
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
constexpr std::uint32_t kNewVertex = std::numeric_limits<std::uint32_t>::max();
struct VertexInfo {
    std::uint32_t index = kNewVertex;  ///< index in Triangulation::vertices
};
struct FaceInfo {
    int parity = -1;  ///< number of input edges crossed from outside, mod 2; -1 = not reached
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<FaceInfo, Kernel>;
using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using CdtPlus = CGAL::Constrained_triangulation_plus_2<Cdt>;

/// Odd winding rule by flood fill from the infinite face: crossing an edge that input edges
/// run along k times flips inside/outside k times. A segment given twice (the zero-width
/// bridges of clipRing, two rings sharing an edge) therefore encloses nothing, as with the
/// winding rule of the GLU tessellator this replaces.
void markInside(CdtPlus& cdt) {
    std::queue<CdtPlus::Face_handle> todo;
    cdt.infinite_face()->info().parity = 0;
    todo.push(cdt.infinite_face());
    while (!todo.empty()) {
        const CdtPlus::Face_handle f = todo.front();
        todo.pop();
        for (int i = 0; i < 3; ++i) {
            const CdtPlus::Face_handle n = f->neighbor(i);
            if (n->info().parity != -1) continue;
            std::size_t crossings = 0;
            if (f->is_constrained(i)) {
                crossings = cdt.number_of_enclosing_constraints(f->vertex(CdtPlus::cw(i)), f->vertex(CdtPlus::ccw(i)));
            }
            n->info().parity = (f->info().parity + static_cast<int>(crossings % 2)) % 2;
            todo.push(n);
        }
    }
}

}  // namespace

Triangulation triangulate(std::span<const std::vector<PlanarPoint>> rings) {
    Triangulation result;
    PlanarPoint origin;
    bool have_origin = false;
    for (const auto& ring : rings) {
        if (ring.size() < 3) continue;
        if (!have_origin) {
            origin = ring[0];  // triangulate near zero for precise intersection points
            have_origin = true;
        }
        for (const auto& p : ring) {
            if (!std::isfinite(p.x) || !std::isfinite(p.y)) {  // CGAL's predicates need finite input
                result.vertices.clear();
                result.ok = false;
                return result;
            }
            result.vertices.push_back(p);
        }
    }
    if (!have_origin) return result;

    try {
        CdtPlus cdt;
        std::uint32_t index = 0;
        std::vector<CdtPlus::Vertex_handle> handles;
        for (const auto& ring : rings) {
            if (ring.size() < 3) continue;
            handles.clear();
            for (const auto& p : ring) {
                const CdtPlus::Vertex_handle v = cdt.insert(Kernel::Point_2(p.x - origin.x, p.y - origin.y));
                if (v->info().index == kNewVertex) v->info().index = index;  // repeated points keep the first index
                ++index;
                // Consecutive repeated points give no edge (CGAL would reject a zero-length constraint).
                if (handles.empty() || handles.back() != v) handles.push_back(v);
            }
            while (handles.size() > 1 && handles.back() == handles.front()) handles.pop_back();
            for (std::size_t i = 0; i < handles.size() && handles.size() >= 2; ++i) {
                cdt.insert_constraint(handles[i], handles[(i + 1) % handles.size()]);
            }
        }
        if (cdt.dimension() < 2) return result;  // all points collinear: no area, no triangles
        markInside(cdt);
        for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
            if (f->info().parity != 1) continue;
            for (int i = 0; i < 3; ++i) {
                VertexInfo& info = f->vertex(i)->info();
                if (info.index == kNewVertex) {  // created where constraints cross
                    info.index = static_cast<std::uint32_t>(result.vertices.size());
                    const Kernel::Point_2& p = f->vertex(i)->point();
                    result.vertices.push_back({p.x() + origin.x, p.y() + origin.y});
                }
                result.indices.push_back(info.index);  // CGAL faces are counter-clockwise
            }
        }
    } catch (const std::exception&) {  // CGAL precondition/assertion failures are exceptions
        result.indices.clear();
        result.ok = false;
    }
    return result;
}

double triangulatedArea(const Triangulation& t) {
    double area = 0;
    for (std::size_t i = 0; i + 2 < t.indices.size(); i += 3) {
        const PlanarPoint& a = t.vertices[t.indices[i]];
        const PlanarPoint& b = t.vertices[t.indices[i + 1]];
        const PlanarPoint& c = t.vertices[t.indices[i + 2]];
        area += 0.5 * std::abs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
    }
    return area;
}

}  // namespace navmap::map
