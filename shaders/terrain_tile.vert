// Terrain of one tile: grid + skirts, positions tile-local; the view matrix is relative to the
// tile origin (computed in double on the CPU), so nothing jitters far from the store origin.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform float u_tile_size;

out vec3 v_normal;
out vec2 v_uv;
out float v_height;
out float v_distance;

void main() {
    vec4 view_pos = u_view * vec4(a_position, 1.0);
    v_normal = a_normal;
    v_uv = a_position.xy / u_tile_size;
    v_height = a_position.z;
    v_distance = length(view_pos.xyz);
    gl_Position = u_projection * view_pos;
}
