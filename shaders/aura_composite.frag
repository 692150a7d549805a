// SPDX-License-Identifier: Apache-2.0
// Transparency label aura (seed 5.5.1, step 4): the scene behind the labels (step 2: buildings
// not in front of a label, roads over them, over the terrain kept before the buildings) blended
// over the frame by the gradient mask (step 3). Inside the auras the depth becomes the
// terrain's, so the labels drawn next are not hidden by the faded buildings. Drawn with
// aura_mask.vert over the enlarged OOBBs; where boxes overlap, only the nearest one (the one
// the label depth buffer kept) composites, so every pixel blends once.
flat in float v_depth;

uniform sampler2D u_behind;              // step 2 layer, premultiplied
uniform sampler2D u_terrain;             // terrain colour before the buildings
uniform sampler2D u_mask;                // step 3: aura gradient
uniform highp sampler2D u_terrain_depth; // window depth of the terrain alone
uniform highp sampler2D u_label_depth;   // window depth of the nearest enlarged label OOBB
uniform float u_min_alpha;               // building opacity kept at the centre of an aura

out vec4 o_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (abs(texelFetch(u_label_depth, p, 0).r - v_depth) > 2e-6) discard;  // a nearer box owns it
    float m = texelFetch(u_mask, p, 0).r * (1.0 - u_min_alpha);
    if (m <= 0.0) discard;
    vec4 behind = texelFetch(u_behind, p, 0);
    vec3 scene = behind.rgb + (1.0 - behind.a) * texelFetch(u_terrain, p, 0).rgb;
    o_color = vec4(scene, m);
    gl_FragDepth = texelFetch(u_terrain_depth, p, 0).r;
}
