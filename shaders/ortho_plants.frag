// SPDX-License-Identifier: Apache-2.0
// A plant's crown in the network's colour at the pixel (seed 6.7.5) with its pair-wise brightness
// change and a shading across the crown that averages out over the disc (lighter middle, darker
// rim: 2/3 is the mean distance from the centre over a disc).
in vec2 v_local;
flat in float v_variation;

uniform sampler2D u_basic;

out vec4 o_color;

void main() {
    float d = length(v_local);
    if (d > 1.0) discard;
    vec3 base = texelFetch(u_basic, ivec2(gl_FragCoord.xy), 0).rgb;
    vec3 c = base * (1.0 + v_variation) * (1.0 + 0.3 * (2.0 / 3.0 - d));
    o_color = vec4(clamp(c, 0.0, 1.0), 1.0);
}
