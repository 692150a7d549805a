// SPDX-License-Identifier: Apache-2.0
// Guidance overlay (guidance_overlay_pass.cpp): the manoeuvre symbol's triangles and the panel
// behind it, in screen pixels (origin top left, y down).
layout(location = 0) in vec2 a_px;

uniform vec2 u_viewport;  // pixels

void main() {
    gl_Position = vec4(a_px.x / u_viewport.x * 2.0 - 1.0, 1.0 - a_px.y / u_viewport.y * 2.0, 0.0, 1.0);
}
