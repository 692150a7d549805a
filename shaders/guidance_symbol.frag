// SPDX-License-Identifier: Apache-2.0
// Guidance overlay: one colour per draw (straight alpha, blended over the frame).
uniform vec4 u_color;

layout(location = 0) out vec4 o_color;

void main() {
    o_color = u_color;
}
