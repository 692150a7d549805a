// SPDX-License-Identifier: Apache-2.0
#pragma once
// The per-class road style uniforms that the shaders of both road techniques declare alike
// (roads_geo.vert; roads_sv.vert and .frag): u_width, u_casing, u_fill, u_casing_color, and
// u_select, each class's SelectionFade as (a, b) (seed 7.3). Private to render/.

#include <GLES3/gl3.h>

#include <array>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

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

}  // namespace navmap::render::gl
