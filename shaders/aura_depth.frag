// SPDX-License-Identifier: Apache-2.0
// Transparency label aura (seed 5.5.1), with aura_mask.vert (NAVMAP_FAR_DEPTH) over the enlarged
// label OOBBs, where the gradient mask is above 0 (the same shape as aura_mask.frag), on the
// pixels where a building is seen (the stencil): writes the far plane's depth and no colour, so
// the layer behind the labels is drawn there with the terrain as the only limit (its own test in
// aura_buildings.frag and in the roads' NAVMAP_TERRAIN_CUT), and the labels drawn next are not
// hidden by the buildings that the aura fades. The depth comes from the vertices, so llvmpipe
// tests the stencil before the shader.
in vec2 v_local;
flat in vec4 v_extent;  // half extents (enlarged), margin, alpha

void main() {
    float margin = max(v_extent.z, 1.0);
    vec2 q = abs(v_local) - (v_extent.xy - vec2(margin));
    if ((1.0 - smoothstep(0.0, margin, length(max(q, vec2(0.0))))) * v_extent.w <= 0.0) discard;
}
