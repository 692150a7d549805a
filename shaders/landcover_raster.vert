// Rasterises a tile's land-cover triangles into its land-cover texture (orthographic, tile-local).
layout(location = 0) in vec2 a_position;
layout(location = 1) in vec4 a_color;

uniform float u_tile_size;

out vec4 v_color;

void main() {
    v_color = a_color;
    gl_Position = vec4(a_position / u_tile_size * 2.0 - 1.0, 0.0, 1.0);
}
