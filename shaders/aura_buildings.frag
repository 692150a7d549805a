// SPDX-License-Identifier: Apache-2.0
// Transparency label aura (seed 5.3.3, 5.5.1), with buildings.vert: step 2 draws the buildings
// again offscreen with the inverse depth test: a fragment in front of a label (z_building <
// z_label, the label OOBB depth buffer) is discarded, so what lies behind the label shows
// through. Fragments behind the terrain-only depth are discarded too: step 2 draws over the far
// plane (aura_depth.frag), and hills still hide the buildings.
in vec3 v_color;  // lit and fogged per vertex (buildings.vert)

uniform highp sampler2D u_label_depth;  // window depth of the nearest enlarged label OOBB (1: none), half resolution
uniform vec2 u_frame_size;              // pixels
uniform highp sampler2D u_terrain_depth;  // window depth of the terrain alone

layout(location = 0) out vec4 o_color;

void main() {
    if (gl_FragCoord.z < texture(u_label_depth, gl_FragCoord.xy / u_frame_size).r) discard;
    if (gl_FragCoord.z >= texelFetch(u_terrain_depth, ivec2(gl_FragCoord.xy), 0).r) discard;
    o_color = vec4(v_color, 1.0);
}
