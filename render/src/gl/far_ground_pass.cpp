// SPDX-License-Identifier: Apache-2.0
#include "far_ground_pass.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/type_ptr.hpp>

#include "gpu_tile.h"

namespace navmap::render::gl {

FarGroundPass::FarGroundPass() : m_program(ShaderProgram::fromEmbedded("far_ground.vert", "far_ground.frag")) {
    glGenVertexArrays(1, &m_vao);  // no attributes: the triangle comes from gl_VertexID
}

FarGroundPass::~FarGroundPass() { glDeleteVertexArrays(1, &m_vao); }

void FarGroundPass::draw(const FrameContext& ctx) {
    const Camera& cam = ctx.frame.camera;
    // The plane: the lowest drawn surface (0 m without tiles), so it never rises above the data.
    float ground = std::numeric_limits<float>::max();
    for (const GpuTile* g : ctx.tiles) {
        if (!g->heights.empty()) ground = std::min(ground, *std::min_element(g->heights.begin(), g->heights.end()));
    }
    if (ground == std::numeric_limits<float>::max()) ground = 0.0f;
    const double eye_height = cam.eye.z - ground;
    if (!(eye_height > 0.0) || ctx.viewport.y <= 0.0f) return;  // below the plane: nothing to continue

    const glm::dvec3 forward = glm::normalize(cam.target - cam.eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, cam.up));
    const glm::dvec3 up = glm::cross(right, forward);
    const double half_h = std::tan(glm::radians(cam.fov_y_deg) * 0.5);
    const double half_w = half_h * double(ctx.viewport.x) / double(ctx.viewport.y);
    const MapStyle& style = ctx.style;

    glUseProgram(m_program.id());
    glUniform3fv(m_program.uniform("u_forward"), 1, glm::value_ptr(glm::vec3(forward)));
    glUniform3fv(m_program.uniform("u_right"), 1, glm::value_ptr(glm::vec3(right * half_w)));
    glUniform3fv(m_program.uniform("u_up"), 1, glm::value_ptr(glm::vec3(up * half_h)));
    glUniform1f(m_program.uniform("u_eye_height"), static_cast<float>(eye_height));
    glUniform3fv(m_program.uniform("u_ground_color"), 1, glm::value_ptr(style.far_ground_color));
    glUniform3fv(m_program.uniform("u_sky_color"), 1, glm::value_ptr(style.sky_color));
    glUniform2f(m_program.uniform("u_fog_range"), style.fog_start_m, style.fog_end_m);
    glUniform1f(m_program.uniform("u_brightness"), style.brightness);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LEQUAL);
    glBindVertexArray(m_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
}

}  // namespace navmap::render::gl
