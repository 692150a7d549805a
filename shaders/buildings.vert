// SPDX-License-Identifier: Apache-2.0
// Extruded buildings, flat per-face normals. Small buildings far away collapse (culled).
// The shading is per vertex: the normals are per face, so the lighting is the same at every
// vertex of a face, and fog varies little across a building (on llvmpipe every per-pixel
// instruction is CPU time).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
layout(location = 3) in float a_footprint;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform float u_cull_ratio;  // cull when footprint / distance falls below this
uniform vec3 u_light_dir;
uniform vec3 u_sky_color;
uniform vec2 u_fog_range;
uniform float u_brightness;

out vec3 v_color;  // lit and fogged

void main() {
    vec4 view_pos = u_view * vec4(a_position, 1.0);
    float dist = length(view_pos.xyz);
    if (a_footprint < u_cull_ratio * dist) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    float lambert = max(dot(normalize(a_normal), u_light_dir), 0.0);
    vec3 color = a_color * (0.45 + 0.6 * lambert) * u_brightness;
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, dist);
    v_color = mix(color, u_sky_color, fog * 0.85);
    gl_Position = u_projection * view_pos;
}
