// SPDX-License-Identifier: Apache-2.0
// Rasterises a tile's land-cover triangles into a land-cover texture (orthographic, tile-local).
layout(location = 0) in vec2 a_position;
layout(location = 1) in vec4 a_color;

// The square [u_offset, u_offset + u_extent] of the tile fills the texture: the whole tile, or a
// descendant's part of an ancestor (geomorphing of the land cover, terrain_tile.frag).
uniform vec2 u_offset;
uniform float u_extent;

out vec4 v_color;

void main() {
    v_color = a_color;
    gl_Position = vec4((a_position - u_offset) / u_extent * 2.0 - 1.0, 0.0, 1.0);
}
