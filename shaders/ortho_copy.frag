// SPDX-License-Identifier: Apache-2.0
// Copies the finished basic orthoimage (the network's output) into the tile's texture. The
// procedural detail of seed 6.7 is drawn over it after this copy, taking its colour from the basic
// layer, which is why the network does not draw into the tile's texture directly.
uniform sampler2D u_basic;

out vec4 o_color;

void main() { o_color = vec4(texelFetch(u_basic, ivec2(gl_FragCoord.xy), 0).rgb, 1.0); }
