// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/triangulator.h"

#include <GL/glu.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <deque>

namespace navmap::map {

namespace {

struct TessState {
    std::deque<std::array<GLdouble, 3>> coords;  // stable addresses for GLU
    Triangulation* out = nullptr;
    PlanarPoint origin;
    bool error = false;
};

void GLAPIENTRY onBegin(GLenum, void*) {}
void GLAPIENTRY onEdgeFlag(GLboolean, void*) {}  // presence forces GL_TRIANGLES output
void GLAPIENTRY onVertex(void* vertex, void* user) {
    auto* st = static_cast<TessState*>(user);
    st->out->indices.push_back(static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(vertex)));
}
void GLAPIENTRY onCombine(GLdouble coords[3], void*[4], GLfloat[4], void** out_data, void* user) {
    auto* st = static_cast<TessState*>(user);
    const auto index = static_cast<std::uintptr_t>(st->out->vertices.size());
    st->out->vertices.push_back({coords[0] + st->origin.x, coords[1] + st->origin.y});
    *out_data = reinterpret_cast<void*>(index);
}
void GLAPIENTRY onError(GLenum, void* user) { static_cast<TessState*>(user)->error = true; }

}  // namespace

Triangulation triangulate(std::span<const std::vector<PlanarPoint>> rings) {
    Triangulation result;
    TessState st;
    st.out = &result;
    bool have_origin = false;
    for (const auto& ring : rings) {
        if (ring.size() < 3) continue;
        if (!have_origin) {
            st.origin = ring[0];  // tessellate near zero for precision
            have_origin = true;
        }
        for (const auto& p : ring) result.vertices.push_back(p);
    }
    if (!have_origin) return result;

    GLUtesselator* tess = gluNewTess();
    if (tess == nullptr) {
        result.ok = false;
        return result;
    }
    using Fn = _GLUfuncptr;
    gluTessCallback(tess, GLU_TESS_BEGIN_DATA, reinterpret_cast<Fn>(&onBegin));
    gluTessCallback(tess, GLU_TESS_EDGE_FLAG_DATA, reinterpret_cast<Fn>(&onEdgeFlag));
    gluTessCallback(tess, GLU_TESS_VERTEX_DATA, reinterpret_cast<Fn>(&onVertex));
    gluTessCallback(tess, GLU_TESS_COMBINE_DATA, reinterpret_cast<Fn>(&onCombine));
    gluTessCallback(tess, GLU_TESS_ERROR_DATA, reinterpret_cast<Fn>(&onError));
    gluTessProperty(tess, GLU_TESS_WINDING_RULE, GLU_TESS_WINDING_ODD);
    gluTessNormal(tess, 0, 0, 1);

    gluTessBeginPolygon(tess, &st);
    std::uintptr_t index = 0;
    for (const auto& ring : rings) {
        if (ring.size() < 3) continue;
        gluTessBeginContour(tess);
        for (const auto& p : ring) {
            st.coords.push_back({p.x - st.origin.x, p.y - st.origin.y, 0.0});
            gluTessVertex(tess, st.coords.back().data(), reinterpret_cast<void*>(index++));
        }
        gluTessEndContour(tess);
    }
    gluTessEndPolygon(tess);
    gluDeleteTess(tess);

    if (st.error || result.indices.size() % 3 != 0) {
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
