// SPDX-License-Identifier: Apache-2.0
// SDF label text: fill, dark outline and light halo in one pass (seed 4.5.2, Fig. 4.7).
// Output is premultiplied (blend ONE, ONE_MINUS_SRC_ALPHA).

uniform sampler2D u_atlas;

in vec2 v_uv;
in float v_dist_scale;
flat in vec4 v_fill;
flat in vec4 v_outline;
flat in vec4 v_halo;
flat in vec2 v_widths;
flat in float v_alpha;

out vec4 o_color;

// The atlas sampled bilinearly in float arithmetic here rather than by the texture unit: drivers
// filter 8-bit textures with weights of their own precision (llvmpipe's differ between x86-64 and
// AArch64), and the distance is scaled up by v_dist_scale, so a last-bit difference in the filter
// moved every glyph edge. Same footprint as GL_LINEAR with CLAMP_TO_EDGE on a level-0 texture.
float atlasDistance(vec2 uv) {
    ivec2 size = textureSize(u_atlas, 0);
    vec2 p = uv * vec2(size) - 0.5;
    vec2 f = p - floor(p);
    ivec2 i0 = ivec2(floor(p));
    ivec2 lo = ivec2(0);
    ivec2 hi = size - 1;
    ivec2 a = clamp(i0, lo, hi);
    ivec2 b = clamp(i0 + 1, lo, hi);
    float t00 = texelFetch(u_atlas, ivec2(a.x, a.y), 0).r;
    float t10 = texelFetch(u_atlas, ivec2(b.x, a.y), 0).r;
    float t01 = texelFetch(u_atlas, ivec2(a.x, b.y), 0).r;
    float t11 = texelFetch(u_atlas, ivec2(b.x, b.y), 0).r;
    return mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
}

void main() {
    float d = (atlasDistance(v_uv) - 0.5) * v_dist_scale;  // px, positive inside the glyph
    float w = 0.5 * clamp(fwidth(d), 0.5, 2.0);                  // about one pixel of antialiasing
    float o = v_widths.x;
    float h = v_widths.y;
    float fill_a = smoothstep(-w, w, d);
    float outline_a = o > 0.0 ? smoothstep(-w, w, d + o) : 0.0;
    // The halo is opaque up to half its width and fades out over the other half.
    float halo_a = h > 0.0 ? smoothstep(-(o + h), -(o + 0.5 * h), d) : 0.0;
#ifdef NAVMAP_TEXT_IDS
    // Occlusion measurement: the label's ink (fill and outline) in the colour naming it.
    if (max(fill_a, outline_a) < 0.5) discard;
    o_color = vec4(v_fill.rgb, 1.0);
    return;
#endif
    vec4 color = vec4(v_halo.rgb, 1.0) * (v_halo.a * halo_a);
    vec4 layer = vec4(v_outline.rgb, 1.0) * (v_outline.a * outline_a);
    color = layer + color * (1.0 - layer.a);
    layer = vec4(v_fill.rgb, 1.0) * (v_fill.a * fill_a);
    color = layer + color * (1.0 - layer.a);
    color *= v_alpha;
    if (color.a < 1.0 / 512.0) discard;
    o_color = color;
}
