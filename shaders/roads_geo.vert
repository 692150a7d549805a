// Cartographic roads, geometric approach (seed 3.4): one quad per draped segment, expanded here
// from the segment's end points (ES 3.0 has no geometry shader), large enough to hold both
// rounded caps. Also draws the route (u_route = 1) with its own width and colour.
layout(location = 0) in vec3 a_p0;
layout(location = 1) in vec3 a_p1;
layout(location = 2) in float a_class;
layout(location = 3) in vec2 a_cap_reach;  // beyond p0, p1: half widths (1: the whole cap)
layout(location = 4) in vec2 a_measure;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform float u_width[11];      // fill width per road class, metres
uniform float u_casing[11];     // extra casing width per side, metres (0: none)
uniform int u_pass;             // 0 casing, 1 fill
uniform int u_route;            // 1: route mode
uniform float u_route_width;
uniform float u_route_casing_m; // route casing per side, metres
uniform vec3 u_scale;           // threshold m, max scale, z-offset alpha
uniform vec3 u_fill[11];        // fill colour per road class
uniform vec3 u_casing_color[11];
uniform vec3 u_route_color;
uniform vec3 u_route_casing;
uniform int u_whole_caps;       // 1: both whole caps on every quad (MapLayers::trim_joint_caps off)
uniform float u_short_half_length;  // kShortPieceHalfLength

// seed 3.4's quad-local coordinates, scaled so that the cap test needs no division: x along
// and y across the segment, both in half widths from its centre (the quad spans |x| <= L + 1,
// |y| <= 1), with L = d / w the half length of the segment in half widths. The seed's
// x_cap = (|x_q| - 1) / h + 1 with x_q in [-1, 1] and h = w / (d + w) is then |x| - L. Per quad
// values are flat: llvmpipe sets up an interpolated input per triangle, a flat one costs a copy.
out vec2 v_cap;
flat out float v_half_length;   // L
flat out vec3 v_color;          // of this pass, per quad (an indexed uniform per fragment costs more)
#ifdef NAVMAP_ROUTE_PROGRESS
out float v_measure;            // metres along the route
#endif

void main() {
    int cls = int(a_class + 0.5);
    float width = u_route == 1 ? u_route_width : u_width[cls];
    if (u_pass == 0 && u_route == 0 && u_casing[cls] <= 0.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // no casing for this class: clipped away
        return;
    }
    if (u_pass == 0) width += 2.0 * (u_route == 1 ? u_route_casing_m : u_casing[cls]);
    // seed 3.6.3: distance-based width scaling beyond a threshold.
    vec3 mid = 0.5 * (a_p0 + a_p1);
    float dist = length((u_view * vec4(mid, 1.0)).xyz);
    width *= clamp(dist / u_scale.x, 1.0, u_scale.y);

    vec2 d = a_p1.xy - a_p0.xy;
    float len = length(d);
    vec2 t = len > 1e-6 ? d / len : vec2(1.0, 0.0);
    vec2 n = vec2(-t.y, t.x);
    // Triangle strip corners: 0 (-,+) 1 (-,-) 2 (+,+) 3 (+,-).
    int corner = gl_VertexID & 3;  // 4 vertices per quad, or a 4-vertex strip per instance
    float sx = corner >= 2 ? 1.0 : -1.0;
    float sy = (corner == 0 || corner == 2) ? 1.0 : -1.0;
    vec3 base = sx < 0.0 ? a_p0 : a_p1;
    // Q_i = P +- n' +- t' with n' = 0.5 w n, t' = 0.5 w t (seed 3.4); at a joint t' only as far as
    // the bend needs (the next piece's quad covers the rest of the cap).
    // A piece shorter than its half width keeps both whole caps (road_style.h, capReach()).
    v_half_length = len / width;
    float reach = u_whole_caps == 1 || v_half_length < u_short_half_length ? 1.0 : (sx < 0.0 ? a_cap_reach.x : a_cap_reach.y);
    vec3 pos = base + vec3(0.5 * width * (sy * n + sx * reach * t), 0.0);
    v_cap = vec2(sx * (v_half_length + reach), sy);
#ifdef NAVMAP_ROUTE_PROGRESS
    v_measure = sx < 0.0 ? a_measure.x : a_measure.y;
#endif
    if (u_route == 1) v_color = u_pass == 0 ? u_route_casing : u_route_color;
    else v_color = u_pass == 0 ? u_casing_color[cls] : u_fill[cls];
    vec4 view_pos = u_view * vec4(pos, 1.0);
    // seed 3.6.2: scale in view space by (1 - alpha) against z-fighting; unlike a world-space
    // offset this does not make roads hover when seen from close by.
    view_pos.xyz *= (1.0 - u_scale.z);
    gl_Position = u_projection * view_pos;
}
