// SPDX-License-Identifier: Apache-2.0
// Transparency label aura (seed 5.5.1, step 4): the scene behind the labels (step 2: the terrain
// before the buildings, the buildings not in front of a label and the roads over them) blended
// over the frame by the gradient mask (step 3). Drawn with aura_mask.vert over the enlarged
// OOBBs, on the pixels where a building is seen (the stencil, which also makes every pixel blend
// once). The labels drawn next must not be hidden by the faded buildings: the depth inside the
// auras is the far plane's, set before step 2 and kept by the frame where step 2 drew with a copy
// of its depth (NAVMAP_DEPTH_KEPT, single-sampled: no depth written here, so llvmpipe tests the
// stencil before the shader); multisampled, step 2 drew into the frame's depth and the terrain's
// is written here.
uniform sampler2D u_behind;              // step 2 layer: opaque, or premultiplied (u_over_terrain)
uniform int u_over_terrain;              // 1: u_behind goes over u_terrain (multisampled targets)
uniform sampler2D u_terrain;             // terrain colour before the buildings
uniform sampler2D u_mask;                // step 3: aura gradient, half resolution, linear filtering
uniform vec2 u_frame_size;               // pixels
#ifndef NAVMAP_DEPTH_KEPT
uniform highp sampler2D u_terrain_depth; // window depth of the terrain alone
#endif
uniform float u_min_alpha;               // building opacity kept at the centre of an aura

out vec4 o_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float m = texture(u_mask, gl_FragCoord.xy / u_frame_size).r * (1.0 - u_min_alpha);
    vec4 behind = texelFetch(u_behind, p, 0);
    vec3 scene = behind.rgb;
    if (u_over_terrain == 1) scene += (1.0 - behind.a) * texelFetch(u_terrain, p, 0).rgb;
    o_color = vec4(scene, m);
#ifndef NAVMAP_DEPTH_KEPT
    gl_FragDepth = texelFetch(u_terrain_depth, p, 0).r;
#endif
}
