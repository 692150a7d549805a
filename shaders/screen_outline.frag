// SPDX-License-Identifier: Apache-2.0
// seed 3.6.3 "Outlines": edge strength = local maximum of road intensity in a 3x3 neighbourhood
// minus the intensity here, blended dark over the scene. Unfiltered texel fetches: on llvmpipe a
// bilinear fetch costs about four of them. u_mask: the mask of the variant, one name for all.
#if defined(NAVMAP_EDGE_MASK)
// The edge pixels themselves, found on the CPU from the mask read back (outlineEdges in
// outline_cells.cpp, software rasterizers): bit x & 7 of texel (x / 8, y), 0 on road pixels.
uniform highp usampler2D u_mask;
#elif defined(NAVMAP_PACKED_MASK)
// The mask bit-packed by outline_pack.frag, and the road pixels left out by the stencil
// (outline_pass.cpp, kRoadStencilBit): here is 0, and the maximum is whether any of the three
// bits around this pixel is set in the rows below, here and above.
uniform highp usampler2D u_mask;
#else
uniform sampler2D u_mask;
#endif
uniform vec3 u_outline_color;
uniform float u_strength;

out vec4 o_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
#if defined(NAVMAP_EDGE_MASK)
    float edge = float((texelFetch(u_mask, ivec2(p.x >> 3, p.y), 0).r >> uint(p.x & 7)) & 1u);
#elif defined(NAVMAP_PACKED_MASK)
    int top = textureSize(u_mask, 0).y - 1;
    int g = p.x >> 3;
    uint rows = texelFetch(u_mask, ivec2(g, max(p.y - 1, 0)), 0).r | texelFetch(u_mask, ivec2(g, p.y), 0).r |
                texelFetch(u_mask, ivec2(g, min(p.y + 1, top)), 0).r;
    // Pixel x is bit (x & 7) + 1 of its group; its neighbours and itself bits (x & 7) .. (x & 7) + 2.
    float edge = ((rows >> uint(p.x & 7)) & 7u) != 0u ? 1.0 : 0.0;
#else
    ivec2 hi = textureSize(u_mask, 0) - 1;
    float here = texelFetch(u_mask, p, 0).r;
    float m = 0.0;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            m = max(m, texelFetch(u_mask, clamp(p + ivec2(dx, dy), ivec2(0), hi), 0).r);
        }
    }
    float edge = clamp(m - here, 0.0, 1.0);
#endif
    // No discard: an edge of 0 blends to no change.
    o_color = vec4(u_outline_color, edge * u_strength);
}
