// SPDX-License-Identifier: Apache-2.0
#include "far_ground_pass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_work.h"
#include "gpu_tile.h"

namespace navmap::render::gl {

FarGroundPass::FarGroundPass() : m_program(ShaderProgram::fromEmbedded("far_ground.vert", "far_ground.frag")) {
    glGenVertexArrays(1, &m_vao);  // no attributes: the corners come from gl_VertexID
}

FarGroundPass::~FarGroundPass() { glDeleteVertexArrays(1, &m_vao); }

namespace {

/// Whether the ground seen through the four screen corners (rays to the plane `eye_height` below
/// the eye, all pointing down) lies within the drawn tiles' bounds and the camera's far plane:
/// then the terrain covers the whole view and the pass is left out (it would only test depth).
/// The visible ground lies between the eye's nadir and those points (the terrain is no lower
/// than the plane), so the box test is conservative for tiles without gaps (the view's selection).
bool coveredByTiles(const FrameContext& ctx, glm::dvec3 r, glm::dvec3 u, double eye_height, glm::dvec3 forward) {
    if (ctx.tiles.empty()) return false;
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (const GpuTile* g : ctx.tiles) {
        lo = glm::min(lo, glm::dvec2(g->origin));
        hi = glm::max(hi, glm::dvec2(g->origin) + glm::dvec2(g->size_m));
    }
    const Camera& cam = ctx.frame.camera;
    auto inside = [&](glm::dvec2 p) { return p.x >= lo.x && p.y >= lo.y && p.x <= hi.x && p.y <= hi.y; };
    if (!inside(glm::dvec2(cam.eye))) return false;
    for (const glm::dvec2 c : {glm::dvec2(-1, -1), glm::dvec2(1, -1), glm::dvec2(1, 1), glm::dvec2(-1, 1)}) {
        const glm::dvec3 ray = forward + c.x * r + c.y * u;  // z < 0
        const double t = eye_height / -ray.z;
        // Depth along the view axis: what the far plane clips.
        if (t * glm::dot(ray, forward) >= cam.far_m || !inside(glm::dvec2(cam.eye + ray * t))) return false;
    }
    return true;
}

}  // namespace

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
    // The screen below the horizon: the NDC square clipped to the half-plane where the view ray
    // points down, dir.z = forward.z + x right.z + y up.z < 0 (one Sutherland-Hodgman step).
    const glm::dvec3 r = right * half_w, u = up * half_h;
    auto down = [&](glm::dvec2 p) { return forward.z + p.x * r.z + p.y * u.z; };
    const glm::dvec2 square[4] = {{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}};
    std::array<glm::vec2, 5> corners{};
    int n = 0;
    for (int i = 0; i < 4; ++i) {
        const glm::dvec2 a = square[i], b = square[(i + 1) % 4];
        const double da = down(a), db = down(b);
        if (da < 0.0) corners[static_cast<std::size_t>(n++)] = glm::vec2(a);
        if ((da < 0.0) != (db < 0.0))
            corners[static_cast<std::size_t>(n++)] = glm::vec2(a + (b - a) * (da / (da - db)));
    }
    if (n < 3) return;  // the whole view is above the horizon
    if (n == 4 && down(square[0]) < 0.0 && down(square[2]) < 0.0 && coveredByTiles(ctx, r, u, eye_height, forward))
        return;  // no horizon in view and all the ground in view lies on the drawn tiles

    glUseProgram(m_program.id());
    glUniform2fv(m_program.uniform("u_corners"), n, glm::value_ptr(corners[0]));
    glUniform3fv(m_program.uniform("u_forward"), 1, glm::value_ptr(glm::vec3(forward)));
    glUniform3fv(m_program.uniform("u_right"), 1, glm::value_ptr(glm::vec3(r)));
    glUniform3fv(m_program.uniform("u_up"), 1, glm::value_ptr(glm::vec3(u)));
    glUniform1f(m_program.uniform("u_eye_height"), static_cast<float>(eye_height));
    glUniform3fv(m_program.uniform("u_ground_color"), 1, glm::value_ptr(style.far_ground_color));
    glUniform3fv(m_program.uniform("u_sky_color"), 1, glm::value_ptr(style.sky_color));
    glUniform2f(m_program.uniform("u_fog_range"), style.fog_start_m, style.fog_end_m);
    glUniform1f(m_program.uniform("u_brightness"), style.brightness);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LEQUAL);
    glBindVertexArray(m_vao);
    countedDrawArrays(GL_TRIANGLE_FAN, 0, n);
    glBindVertexArray(0);
}

}  // namespace navmap::render::gl
