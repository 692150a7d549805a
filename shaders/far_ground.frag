// SPDX-License-Identifier: Apache-2.0
// The ground beyond the data: the view ray meets a level plane u_eye_height below the eye, in
// the neutral ground colour, with the terrain's aerial perspective (terrain_tile.vert). Only the
// part of the screen below the horizon is drawn (far_ground.vert), and without a discard, so that
// a software rasterizer tests depth before shading.
uniform vec3 u_forward;  // the view direction, and the screen's half extents at unit distance
uniform vec3 u_right;
uniform vec3 u_up;
uniform float u_eye_height;  // metres above the plane
uniform vec3 u_ground_color;
uniform vec3 u_sky_color;
uniform vec2 u_fog_range;
uniform float u_brightness;

in vec2 v_ndc;
out vec4 o_color;

void main() {
    vec3 dir = normalize(u_forward + v_ndc.x * u_right + v_ndc.y * u_up);
    float distance = u_eye_height / max(-dir.z, 1e-6);
    float fog = 0.85 * smoothstep(u_fog_range.x, u_fog_range.y, distance);
    o_color = vec4(u_ground_color * u_brightness * (1.0 - fog) + u_sky_color * fog, 1.0);
}
