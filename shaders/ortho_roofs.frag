// SPDX-License-Identifier: Apache-2.0
// Building roofs (seed 6.7.3): flat polygons in the network's colour at the pixel with a pair-wise
// slight change of brightness and hue; in the shadow pass (u_shadow 1) the footprint, moved away
// from the light, darkens the ground beside the building (blended).
in vec2 v_position;
flat in vec4 v_params;  // variation, hue, height (m)

uniform sampler2D u_basic;
uniform float u_shadow;

out vec4 o_color;

void main() {
    if (u_shadow > 0.5) {
        o_color = vec4(0.0, 0.0, 0.0, 0.45);
        return;
    }
    vec3 base = texelFetch(u_basic, ivec2(gl_FragCoord.xy), 0).rgb;
    float luma = dot(base, vec3(0.299, 0.587, 0.114));
    vec3 c = base * (1.0 + v_params.x) + v_params.y * luma * vec3(1.0, 0.0, -1.0);
    o_color = vec4(clamp(c, 0.0, 1.0), 1.0);
}
