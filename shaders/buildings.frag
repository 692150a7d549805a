// SPDX-License-Identifier: Apache-2.0
in vec3 v_color;  // lit and fogged per vertex (buildings.vert)

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_road;  // buildings hide roads: no outline on them

void main() {
    o_color = vec4(v_color, 1.0);
    o_road = vec4(0.0);
}
