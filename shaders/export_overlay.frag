// SPDX-License-Identifier: Apache-2.0
// The overlay blended over an exported dma-buf frame (dmabuf_export.cpp), e.g. the map data
// attribution: premultiplied RGBA texels at u_origin. The buffer's rows run top first like the
// overlay's, so a fragment's coordinates minus the origin are its texel; a scissor bounds the draw.
uniform sampler2D u_overlay;
uniform ivec2 u_origin;

out vec4 o_color;

void main() { o_color = texelFetch(u_overlay, ivec2(gl_FragCoord.xy) - u_origin, 0); }
