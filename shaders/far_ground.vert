// SPDX-License-Identifier: Apache-2.0
// The ground beyond the data (far_ground_pass.h): one triangle over the whole screen at the far
// depth, so that it only fills what nothing else has drawn.
out vec2 v_ndc;

void main() {
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    v_ndc = p;
    gl_Position = vec4(p, 1.0, 1.0);
}
