// SPDX-License-Identifier: Apache-2.0
// The orthoimage network on the GPU (seed 6.6.2, Fig. 6.11): per pixel, the compressed input
// vector (NAVMAP_ORTHO_TEXELS texels of two (node, value) byte pairs, one plane of the input
// texture per texel) selects the rows of w0 to add: eq. 6.1 over the active inputs only
// (h 2m multiply-adds instead of n h), then the sigmoid (6.2) and the linear output layer (6.3,
// 3 h multiply-adds). Hidden neurons are packed by four (padding neurons have zero output
// weights). Output: the basic orthoimage (sRGB), clamped as the CPU reference's color() clamps.
#ifndef NAVMAP_ORTHO_INPUTS
#define NAVMAP_ORTHO_INPUTS 43
#endif
#ifndef NAVMAP_ORTHO_HIDDEN4
#define NAVMAP_ORTHO_HIDDEN4 11
#endif
#ifndef NAVMAP_ORTHO_TEXELS
#define NAVMAP_ORTHO_TEXELS 5
#endif
precision highp usampler2D;

uniform usampler2D u_inputs;  // RGBA8UI: (node, value, node, value); plane k at rows k * u_size
uniform int u_size;

layout(std140) uniform OrthoWeights {
    vec4 w0[NAVMAP_ORTHO_INPUTS * NAVMAP_ORTHO_HIDDEN4];  // row per input node
    vec4 b0[NAVMAP_ORTHO_HIDDEN4];
    vec4 w1[3 * NAVMAP_ORTHO_HIDDEN4];  // per output channel
    vec4 b1;
};

out vec4 o_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 a[NAVMAP_ORTHO_HIDDEN4];
    for (int j = 0; j < NAVMAP_ORTHO_HIDDEN4; ++j) a[j] = b0[j];
    for (int k = 0; k < NAVMAP_ORTHO_TEXELS; ++k) {
        uvec4 t = texelFetch(u_inputs, ivec2(p.x, p.y + k * u_size), 0);
        int r0 = int(t.x) * NAVMAP_ORTHO_HIDDEN4, r1 = int(t.z) * NAVMAP_ORTHO_HIDDEN4;
        float v0 = float(t.y) / 255.0, v1 = float(t.w) / 255.0;
        for (int j = 0; j < NAVMAP_ORTHO_HIDDEN4; ++j) a[j] += w0[r0 + j] * v0 + w0[r1 + j] * v1;
    }
    vec3 rgb = b1.xyz;
    for (int j = 0; j < NAVMAP_ORTHO_HIDDEN4; ++j) {
        vec4 s = 1.0 / (1.0 + exp(-a[j]));
        rgb += vec3(dot(s, w1[j]), dot(s, w1[NAVMAP_ORTHO_HIDDEN4 + j]), dot(s, w1[2 * NAVMAP_ORTHO_HIDDEN4 + j]));
    }
    o_color = vec4(clamp(rgb, 0.0, 1.0), 1.0);
}
