// SPDX-License-Identifier: Apache-2.0
// Procedural detail of an orthoimage (seed 6.7): field parcels, roof and shadow polygons in
// tile-local metres (ortho_generator.cpp); the square [u_offset, u_offset + u_extent] fills the image.
layout(location = 0) in vec2 a_position;
layout(location = 1) in vec4 a_params;  // fields: pattern, variation, hue, angle; roofs: variation, hue, height

uniform vec2 u_offset;
uniform float u_extent;
uniform vec2 u_shift;  // the roofs' shadow pass: the footprint moved away from the light (m per m of height)

out vec2 v_position;
flat out vec4 v_params;

void main() {
    vec2 p = a_position + u_shift * a_params.z;
    v_position = p;
    v_params = a_params;
    gl_Position = vec4((p - u_offset) / u_extent * 2.0 - 1.0, 0.0, 1.0);
}
