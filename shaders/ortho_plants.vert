// SPDX-License-Identifier: Apache-2.0
// Plants of the vegetation simulation (seed 6.7.1) as crowns seen from above: a quad of four
// corners per plant around its circle (ortho_generator.cpp).
layout(location = 0) in vec2 a_centre;  // tile-local metres
layout(location = 1) in vec2 a_corner;  // -1 or 1
layout(location = 2) in vec2 a_plant;   // radius (m), brightness variation

uniform vec2 u_offset;
uniform float u_extent;

out vec2 v_local;  // -1..1 across the crown
flat out float v_variation;

void main() {
    vec2 p = a_centre + a_corner * a_plant.x;
    v_local = a_corner;
    v_variation = a_plant.y;
    gl_Position = vec4((p - u_offset) / u_extent * 2.0 - 1.0, 0.0, 1.0);
}
