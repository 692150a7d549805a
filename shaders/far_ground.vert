// SPDX-License-Identifier: Apache-2.0
// The ground beyond the data (far_ground_pass.h): the part of the screen below the horizon, a
// fan of up to 5 corners in normalized device coordinates, at the far depth so that it only fills
// what nothing else has drawn.
uniform vec2 u_corners[5];
out vec2 v_ndc;

void main() {
    v_ndc = u_corners[gl_VertexID];
    gl_Position = vec4(v_ndc, 1.0, 1.0);
}
