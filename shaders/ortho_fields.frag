// SPDX-License-Identifier: Apache-2.0
// Field parcels (seed 6.7.2) over the farmland of the basic orthoimage. The colour is the network's
// at the pixel (seed 6.7.5), changed by the parcel's pair-wise brightness and hue and by its crop
// pattern: rows whose modulation averages out, so the farmland's mean colour stays the network's.
// Drawn only where the tile's super land cover is farmland (the seed's stencil mask, here a lookup
// of the cover texel), so no parcel reaches beyond the farmland.
precision highp usampler2D;
in vec2 v_position;
flat in vec4 v_params;  // pattern, variation, hue, angle

uniform sampler2D u_basic;
uniform usampler2D u_cover;  // the tile's super land cover (R8UI), row 0 south
uniform float u_tile_size;
uniform uint u_farmland;
uniform float u_mask_only;  // 1: white (tests: the drawn area)
uniform float u_pixel_m;    // metres per pixel of the image

out vec4 o_color;

// The crop atlas: row period (m), contrast, cross rows.
const vec3 kPatterns[8] = vec3[8](vec3(3.0, 0.10, 0.0), vec3(6.0, 0.16, 0.0), vec3(2.0, 0.05, 0.0),
                                  vec3(12.0, 0.08, 0.0), vec3(4.0, 0.12, 1.0), vec3(9.0, 0.20, 0.0),
                                  vec3(5.0, 0.06, 1.0), vec3(16.0, 0.12, 0.0));

void main() {
    ivec2 size = textureSize(u_cover, 0);
    ivec2 texel = clamp(ivec2(floor(v_position / u_tile_size * vec2(size))), ivec2(0), size - 1);
    if (texelFetch(u_cover, texel, 0).r != u_farmland) discard;
    if (u_mask_only > 0.5) {
        o_color = vec4(1.0);
        return;
    }
    vec3 base = texelFetch(u_basic, ivec2(gl_FragCoord.xy), 0).rgb;
    vec3 pattern = kPatterns[clamp(int(v_params.x), 0, 7)];
    vec2 dir = vec2(cos(v_params.w), sin(v_params.w));
    // Rows finer than three pixels are left out: sampled at the pixel centres they would alias into
    // slow stripes whose mean is not zero, moving the parcel's colour (seed 6.7.5).
    float keep_rows = clamp(pattern.x / u_pixel_m - 2.0, 0.0, 1.0);
    float keep_cross = clamp(3.0 * pattern.x / u_pixel_m - 2.0, 0.0, 1.0);
    float rows = keep_rows * sin(6.2831853 * dot(v_position, vec2(-dir.y, dir.x)) / pattern.x);
    float cross = keep_cross * pattern.z * 0.5 * sin(6.2831853 * dot(v_position, dir) / (3.0 * pattern.x));
    float luma = dot(base, vec3(0.299, 0.587, 0.114));
    vec3 c = base * (1.0 + v_params.y) + v_params.z * luma * vec3(1.0, 0.0, -1.0);
    c *= 1.0 + pattern.y * (rows + cross);
    o_color = vec4(clamp(c, 0.0, 1.0), 1.0);
}
