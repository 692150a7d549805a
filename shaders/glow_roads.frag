// SPDX-License-Identifier: Apache-2.0
// Glowing roads (seed 5.3.5, 5.5.2), with roads_geo.vert: the road and route fill drawn again,
// depth-tested GREATER against the scene depth (so only fragments behind something pass) and
// kept only where they lie in front of the terrain-only depth (so what hides them is a
// building, not a hill). Output: the single glow colour or the road's own colour, straight
// into the frame (u_direct = 1, no blur: skipped where a road is visible, road mask of seed
// 3.6.3) or into the glow buffer for the blur.
in vec2 v_cap;
flat in float v_half_length;
flat in vec3 v_color;  // the fill of the road class or the route's colour (pass 1)

uniform highp sampler2D u_terrain_depth;  // window depth of the terrain alone (texelFetch)
uniform int u_road_color;                 // 0: u_glow_color, 1: the road's own fill colour
uniform vec3 u_glow_color;
uniform int u_direct;
uniform sampler2D u_road_mask;            // direct: 1 where a road or the route is visible
uniform float u_alpha;                    // direct: glow strength

layout(location = 0) out vec4 o_color;

void main() {
    // seed 3.4: the same analytic caps as the visible roads.
    float x_cap = abs(v_cap.x) - v_half_length;
    float y_cap = abs(v_cap.y);
    if (x_cap > 0.0 && x_cap * x_cap + y_cap * y_cap > 1.0) discard;
    // seed 5.5.2: z_building < z_road is the hardware test; here z_road <= z_terrain.
    float terrain = texelFetch(u_terrain_depth, ivec2(gl_FragCoord.xy), 0).r;
    if (gl_FragCoord.z > terrain) discard;
    if (u_direct == 1 && texelFetch(u_road_mask, ivec2(gl_FragCoord.xy), 0).r > 0.5) discard;
    vec3 color = u_glow_color;
    if (u_road_color == 1) color = v_color;
    o_color = vec4(color, u_direct == 1 ? u_alpha : 1.0);
}
