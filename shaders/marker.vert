// SPDX-License-Identifier: Apache-2.0
// The vehicle marker (CCP arrow): a constant screen size at the projected vehicle position,
// rotated to the heading as it appears on screen.
layout(location = 0) in vec2 a_corner;  // arrow outline in marker units (tip at +y)

uniform vec4 u_anchor_clip;    // projected vehicle position (clip space)
uniform vec2 u_screen_dir;     // unit heading direction on screen (pixels, y up)
uniform vec2 u_viewport;       // pixels
uniform float u_size_px;

void main() {
    vec2 ndc = u_anchor_clip.xy / u_anchor_clip.w;
    vec2 side = vec2(u_screen_dir.y, -u_screen_dir.x);
    vec2 px = (a_corner.x * side + a_corner.y * u_screen_dir) * u_size_px;
    gl_Position = vec4(ndc + px * 2.0 / u_viewport, 0.0, 1.0);
}
