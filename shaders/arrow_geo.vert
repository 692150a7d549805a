// SPDX-License-Identifier: Apache-2.0
// Manoeuvre arrows and guidance roads (maneuver_arrow_pass.cpp), geometric approach as the route
// (seed 3.4, 3.6.1): one quad per draped piece, expanded here from its end points, the half
// width at each end from the arrow's shape at the end's measure (maneuver_arrow.cpp
// arrowHalfWidth computes the same on the CPU): the shaft, the head narrowing to its tip, the
// casing grown around both (widths and head already scaled per arrow on the CPU: the distance
// scaling of seed 3.6.3 and a least width on screen). Pieces of constant width get the analytic round caps of the roads
// (joints and the tail); the head's pieces end flat, so that they join into one triangle.
layout(location = 0) in vec3 a_p0;
layout(location = 1) in vec3 a_p1;
layout(location = 4) in vec2 a_measure;  // along the arrow, metres

uniform mat4 u_view;
uniform mat4 u_projection;
uniform int u_pass;        // 0 casing, 1 fill
uniform vec4 u_shape;      // head base, fill tip, casing tip, casing per side (metres)
uniform vec2 u_widths;     // half widths: shaft, head at its base (metres)
uniform float u_z_offset;  // seed 3.6.2: view-space scale 1 - this

out vec2 v_cap;
flat out float v_half_length;
flat out float v_round;

// Half width just beyond (after = true) or just before `m`: the width jumps at the head's base.
float halfWidth(float m, bool after) {
    float x = after ? m + 1e-3 : m - 1e-3;
    float head_length = u_shape.y - u_shape.x;
    float slope = head_length > 0.0 ? u_widths.y / head_length : 0.0;
    if (u_pass == 1) return x < u_shape.x ? u_widths.x : max(0.0, (u_shape.y - x) * slope);
    float w = x < u_shape.x ? u_widths.x + u_shape.w : 0.0;
    if (x >= u_shape.x - u_shape.w) w = max(w, (u_shape.z - x) * slope);
    return max(w, 0.0);
}

void main() {
    float w0 = halfWidth(a_measure.x, true), w1 = halfWidth(a_measure.y, false);
    if (w0 <= 0.0 && w1 <= 0.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // nothing of this pass here: clipped away
        return;
    }
    vec2 d = a_p1.xy - a_p0.xy;
    float len = length(d);
    vec2 t = len > 1e-6 ? d / len : vec2(1.0, 0.0);
    vec2 n = vec2(-t.y, t.x);
    int corner = gl_VertexID & 3;  // 0 (-,+) 1 (-,-) 2 (+,+) 3 (+,-)
    float sx = corner >= 2 ? 1.0 : -1.0;
    float sy = (corner == 0 || corner == 2) ? 1.0 : -1.0;
    bool round = abs(w0 - w1) < 1e-4;
    v_round = round ? 1.0 : 0.0;
    float w = sx < 0.0 ? w0 : w1;
    float reach = round ? 1.0 : 0.0;  // whole round caps, in half widths
    vec3 base = sx < 0.0 ? a_p0 : a_p1;
    vec3 pos = base + vec3(w * (sy * n + sx * reach * t), 0.0);
    v_half_length = round ? 0.5 * len / w : 0.0;
    v_cap = vec2(sx * (v_half_length + reach), sy);
    vec4 view_pos = u_view * vec4(pos, 1.0);
    // seed 3.6.2: scaled towards the eye in view space against z-fighting, more than the route,
    // so the arrow lies on it.
    view_pos.xyz *= (1.0 - u_z_offset);
    gl_Position = u_projection * view_pos;
}
