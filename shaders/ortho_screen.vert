// SPDX-License-Identifier: Apache-2.0
// A full-screen triangle over the orthoimage being generated (ortho_generator.cpp): the network
// pass (scissored to a band of rows) and the copy of the finished basic layer into the tile's image;
// the overlay of an exported dma-buf frame (dmabuf_export.cpp, scissored to the overlay).
void main() {
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    gl_Position = vec4(p, 0.0, 1.0);
}
