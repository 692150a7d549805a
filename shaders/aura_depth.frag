// SPDX-License-Identifier: Apache-2.0
// Transparency label aura (seed 5.5.1), with aura_mask.vert over the enlarged label OOBBs, where
// the gradient mask is above 0 (the same shape as aura_mask.frag): writes the terrain's depth
// and no colour, so the layer behind the labels is drawn over the terrain and the labels drawn
// next are not hidden by the buildings that the aura fades.
in vec2 v_local;
flat in vec4 v_extent;  // half extents (enlarged), margin, alpha

uniform highp sampler2D u_terrain_depth;  // window depth of the terrain alone

void main() {
    float margin = max(v_extent.z, 1.0);
    vec2 q = abs(v_local) - (v_extent.xy - vec2(margin));
    if ((1.0 - smoothstep(0.0, margin, length(max(q, vec2(0.0))))) * v_extent.w <= 0.0) discard;
    gl_FragDepth = texelFetch(u_terrain_depth, ivec2(gl_FragCoord.xy), 0).r;
}
