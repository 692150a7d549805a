// SPDX-License-Identifier: Apache-2.0
// The outline filter's cells near roads (OutlineCells, outline_pass.cpp): rectangles in pixels.
layout(location = 0) in vec2 a_pixel;

uniform vec2 u_viewport;

void main() {
    gl_Position = vec4(a_pixel / u_viewport * 2.0 - 1.0, 0.0, 1.0);
}
