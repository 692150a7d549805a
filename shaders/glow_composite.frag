// SPDX-License-Identifier: Apache-2.0
// Glowing roads with blur (seed 5.5.2): the glow buffer composited over the scene before the
// labels, premultiplied alpha; the soft halo surrounds the sharp glow. Where the frame
// already shows a road or the route (road mask of seed 3.6.3) nothing glows: a road hidden
// under a visible one is not hidden by a building.
in vec2 v_uv;

uniform sampler2D u_glow;     // full resolution, premultiplied
uniform sampler2D u_blurred;  // half resolution, premultiplied, linear filtering
uniform sampler2D u_road_mask; // 1 where a road or the route is visible
uniform float u_strength;

out vec4 o_color;

void main() {
    vec4 c = texelFetch(u_glow, ivec2(gl_FragCoord.xy), 0);
    c = max(c, min(texture(u_blurred, v_uv) * 1.5, vec4(1.0)));
    c *= 1.0 - texelFetch(u_road_mask, ivec2(gl_FragCoord.xy), 0).r;
    if (c.a <= 0.0) discard;
    o_color = c * u_strength;
}
