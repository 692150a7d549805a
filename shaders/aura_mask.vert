// SPDX-License-Identifier: Apache-2.0
// Transparency label aura (seed 5.5.1): one enlarged label OOBB per instance, in screen pixels
// (origin top left, y down), at the depth of the label plane. Writes the label depth buffer
// and the gradient mask in one pass.
layout(location = 0) in vec4 a_box;     // center x, y px; axis x, y (unit, along the text)
layout(location = 1) in vec4 a_extent;  // half extents x, y px (enlarged); margin px; alpha
layout(location = 2) in float a_depth;  // NDC z of the label plane

uniform vec2 u_viewport;

out vec2 v_local;  // px from the centre along the box axes
flat out vec4 v_extent;
flat out float v_depth;  // window depth of the label plane

void main() {
    float sx = gl_VertexID >= 2 ? 1.0 : -1.0;
    float sy = (gl_VertexID == 0 || gl_VertexID == 2) ? 1.0 : -1.0;
    vec2 axis = a_box.zw;
    vec2 axis_y = vec2(-axis.y, axis.x);
    v_local = vec2(sx, sy) * a_extent.xy;
    v_extent = a_extent;
    v_depth = a_depth * 0.5 + 0.5;
    vec2 px = a_box.xy + axis * v_local.x + axis_y * v_local.y;
#ifdef NAVMAP_FAR_DEPTH
    float z = 1.0;  // the far plane (aura_depth.frag)
#else
    float z = a_depth;
#endif
    gl_Position = vec4(px.x / u_viewport.x * 2.0 - 1.0, 1.0 - px.y / u_viewport.y * 2.0, z, 1.0);
}
