// SPDX-License-Identifier: Apache-2.0
// Glowing roads from the stencil (seed 5.3.5, 5.5.2), with screen_outline.vert over the frame:
// the stencil test keeps the pixels where the roads' fill pass failed the depth test in front of
// the terrain alone, so where a building hides a road. Nothing glows where a road is seen (road
// mask of seed 3.6.3). Output: the glow colour, straight into the frame (u_alpha: the glow
// strength, blended) or opaque into the glow buffer for the blur (u_alpha 1).
uniform vec3 u_glow_color;
uniform sampler2D u_road_mask;  // 1 where a road or the route is seen
uniform float u_alpha;

out vec4 o_color;

void main() {
    // No discard: the stencil test then runs before the shader, and only the marked pixels pay.
    float keep = texelFetch(u_road_mask, ivec2(gl_FragCoord.xy), 0).r > 0.5 ? 0.0 : 1.0;
    o_color = vec4(u_glow_color * keep, u_alpha * keep);
}
