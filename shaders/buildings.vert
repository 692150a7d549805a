// Extruded buildings, flat per-face normals. Small buildings far away collapse (culled).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
layout(location = 3) in float a_footprint;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform float u_cull_ratio;  // cull when footprint / distance falls below this

out vec3 v_normal;
out vec3 v_color;
out float v_distance;

void main() {
    vec4 view_pos = u_view * vec4(a_position, 1.0);
    float dist = length(view_pos.xyz);
    if (a_footprint < u_cull_ratio * dist) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    v_normal = a_normal;
    v_color = a_color;
    v_distance = dist;
    gl_Position = u_projection * view_pos;
}
