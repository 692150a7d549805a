// SPDX-License-Identifier: Apache-2.0
// Transparency label aura (seed 5.5.1, step 3): the smooth gradient around a label: 1 over the
// label box, falling to 0 at the edge of the enlarged box (rounded at the corners).
in vec2 v_local;
flat in vec4 v_extent;  // half extents (enlarged), margin, alpha

out vec4 o_mask;

void main() {
    float margin = max(v_extent.z, 1.0);
    vec2 q = abs(v_local) - (v_extent.xy - vec2(margin));
    float outside = length(max(q, vec2(0.0)));
    float m = (1.0 - smoothstep(0.0, margin, outside)) * v_extent.w;
    o_mask = vec4(m);
}
