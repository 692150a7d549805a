// SPDX-License-Identifier: Apache-2.0
// Manoeuvre arrows and guidance roads (arrow_geo.vert): the round caps of the constant-width
// pieces cut analytically (seed 3.4, as roads_geo.frag), one colour per pass. With
// NAVMAP_ARROW_GLOW the hidden part shines through buildings (seed 5.5.2, as glow_roads.frag):
// drawn with the depth test GREATER against the scene, kept where it lies in front of the
// terrain alone (what hides it is a building, not a hill).
in vec2 v_cap;
flat in float v_half_length;
flat in float v_round;

uniform vec4 u_color;  // straight alpha
#ifdef NAVMAP_ARROW_GLOW
uniform highp sampler2D u_terrain_depth;  // window depth of the terrain alone (texelFetch)
#endif

layout(location = 0) out vec4 o_color;

void main() {
    if (v_round > 0.5) {
        float x_cap = abs(v_cap.x) - v_half_length;
        float y_cap = abs(v_cap.y);
        if (x_cap > 0.0 && x_cap * x_cap + y_cap * y_cap > 1.0) discard;
    }
#ifdef NAVMAP_ARROW_GLOW
    if (gl_FragCoord.z > texelFetch(u_terrain_depth, ivec2(gl_FragCoord.xy), 0).r) discard;
#endif
    o_color = u_color;
}
