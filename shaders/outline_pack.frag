// SPDX-License-Identifier: Apache-2.0
// The road mask bit-packed for the outline filter (seed 3.6.3): texel (g, y) holds as bits 0..9
// whether the pixels x = 8g - 1 .. 8g + 8 of row y are road pixels, so that the filter reads a
// pixel's 3x3 neighbourhood in three fetches instead of nine. Exact where the mask is binary: the
// road and route passes write 1, and there is no MSAA resolve (outline_pass.cpp). Pixels outside
// the screen repeat the edge pixel, as the unpacked filter clamps its coordinates.
uniform sampler2D u_road_mask;

out uint o_bits;

void main() {
    ivec2 g = ivec2(gl_FragCoord.xy);
    int last = textureSize(u_road_mask, 0).x - 1;
    uint bits = 0u;
    for (int i = 0; i < 10; ++i) {
        int x = 8 * g.x - 1 + i;
        bits |= texelFetch(u_road_mask, ivec2(clamp(x, 0, last), g.y), 0).r > 0.5 ? (1u << uint(i)) : 0u;
    }
    o_bits = bits;
}
