// SPDX-License-Identifier: Apache-2.0
#pragma once
// The per-class road style uniforms that the shaders of both road techniques declare alike
// (roads_geo.vert; roads_sv.vert and .frag): u_width, u_casing, u_fill, u_casing_color, and
// u_select, each class's SelectionFade as (a, b) (seed 7.3); and every uniform of roads_geo.vert
// for one pass of roads or route (RoadPass, RoutePass, the glow). Private to render/.

#include <GLES3/gl3.h>

#include <algorithm>
#include <array>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "frame_context.h"
#include "map_culling.h"
#include "navmap/render/road_style.h"
#include "shader_program.h"

namespace navmap::render::gl {

inline void setRoadClassUniforms(ShaderProgram& p, const RoadStyle& style,
                                 const std::array<SelectionFade, kStyledRoadClasses>& fades) {
    float widths[kStyledRoadClasses], casings[kStyledRoadClasses];
    glm::vec2 select[kStyledRoadClasses];
    glm::vec3 fills[kStyledRoadClasses], casing_colors[kStyledRoadClasses];
    for (std::size_t i = 0; i < kStyledRoadClasses; ++i) {
        widths[i] = style.classes[i].width_m;
        casings[i] = style.classes[i].casing_m;
        select[i] = {fades[i].a, fades[i].b};
        fills[i] = style.classes[i].fill;
        casing_colors[i] = style.classes[i].casing;
    }
    glUniform1fv(p.uniform("u_width"), kStyledRoadClasses, widths);
    glUniform1fv(p.uniform("u_casing"), kStyledRoadClasses, casings);
    glUniform2fv(p.uniform("u_select"), kStyledRoadClasses, glm::value_ptr(select[0]));
    glUniform3fv(p.uniform("u_fill"), kStyledRoadClasses, glm::value_ptr(fills[0]));
    glUniform3fv(p.uniform("u_casing_color"), kStyledRoadClasses, glm::value_ptr(casing_colors[0]));
}

/// With `p` (a roads_geo.vert program) bound: its uniforms for `pass` (0 casing, 1 fill, 2 outline
/// footprint) of the roads or, with `route`, of the route in this frame.
inline void setRoadUniforms(ShaderProgram& p, int pass, bool route, const FrameContext& ctx) {
    glUniformMatrix4fv(p.uniform("u_projection"), 1, GL_FALSE, glm::value_ptr(ctx.projection));
    const RoadStyle& rs = ctx.style.roads;
    setRoadClassUniforms(p, rs, ctx.selection);
    glUniform1i(p.uniform("u_pass"), pass);
    glUniform1i(p.uniform("u_whole_caps"), ctx.whole_caps ? 1 : 0);
    glUniform1f(p.uniform("u_short_half_length"), kShortPieceHalfLength);
    glUniform3f(p.uniform("u_min_width"), std::max(rs.min_width_px, 0.0f), ctx.viewport.x, ctx.viewport.y);
    glUniform1i(p.uniform("u_route"), route ? 1 : 0);
    glUniform1f(p.uniform("u_route_width"), ctx.style.route_width_m);
    glUniform1f(p.uniform("u_route_casing_m"), kRouteCasingFraction * ctx.style.route_width_m);
    glUniform3fv(p.uniform("u_route_color"), 1, glm::value_ptr(ctx.style.route_color));
    glUniform3fv(p.uniform("u_route_casing"), 1, glm::value_ptr(ctx.style.route_casing));
    // The route sits above the roads: a slightly larger view-space offset (seed 3.6.2).
    glUniform3f(p.uniform("u_scale"), rs.scale_threshold_m, rs.max_scale, rs.z_offset_alpha * (route ? 1.5f : 1.0f));
}

}  // namespace navmap::render::gl
