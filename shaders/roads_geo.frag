// SPDX-License-Identifier: Apache-2.0
// seed 3.4: the rounded caps are cut analytically out of the quad. In cap-local coordinates
// x_cap = |x| - L, y_cap = |y| (roads_geo.vert: the seed's x_cap = (|x_q| - 1) / h + 1 in half
// widths); inside the cap region (x_cap > 0) a fragment with x_cap^2 + y_cap^2 > 1 lies outside
// the half circle and is discarded.
in vec2 v_cap;
flat in float v_half_length;
flat in vec3 v_color;  // this pass's colour of the road class or the route
#ifdef NAVMAP_ROUTE_PROGRESS
in float v_measure;
flat in float v_dash_m;  // in a tunnel: the dash period (roads_geo.vert); 0: solid
uniform float u_route_progress;  // metres driven; the part behind is dimmed
#endif

#ifdef NAVMAP_TERRAIN_CUT
// The fragments behind the terrain-only depth are discarded (MapRenderer::terrainCutProgram):
// glowing roads from the stencil (seed 5.5.2), whose fill pass then marks only the fragments that
// something else, a building, hides; the label aura's layer behind the labels (5.5.1), drawn over
// the far plane. A variant of its own: a uniform switch would cost llvmpipe the fetch on every
// road fragment.
uniform highp sampler2D u_terrain_depth;
#endif

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_road;  // road intensity for the screen-space outlines (seed 3.6.3)

void main() {
    float x_cap = abs(v_cap.x) - v_half_length;
    float y_cap = abs(v_cap.y);
    if (x_cap > 0.0 && x_cap * x_cap + y_cap * y_cap > 1.0) discard;
#ifdef NAVMAP_TERRAIN_CUT
    if (gl_FragCoord.z > texelFetch(u_terrain_depth, ivec2(gl_FragCoord.xy), 0).r) discard;
#endif
    vec3 color = v_color;
#ifdef NAVMAP_ROUTE_PROGRESS
    if (v_dash_m > 0.0 && fract(v_measure / v_dash_m) >= 0.5) discard;  // the gaps of a tunnel's dashes
    if (v_measure < u_route_progress) color = mix(color, vec3(0.6), 0.65);  // already driven
#endif
    o_color = vec4(color, 1.0);
    o_road = vec4(1.0);
}
