// SPDX-License-Identifier: Apache-2.0
// Terrain heightfield: positions relative to the mesh origin, normals per vertex.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_view;
uniform mat4 u_projection;

out vec3 v_normal;
out float v_height;
out float v_distance;

void main() {
    vec4 view_pos = u_view * vec4(a_position, 1.0);
    v_normal = a_normal;
    v_height = a_position.z;
    v_distance = length(view_pos.xyz);
    gl_Position = u_projection * view_pos;
}
