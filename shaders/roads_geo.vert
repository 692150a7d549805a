// SPDX-License-Identifier: Apache-2.0
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
uniform mat4 u_view_projection; // u_projection * u_view
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
uniform vec3 u_min_width;       // x: least on-screen width of the fill, pixels (0: off); yz: viewport, pixels
uniform vec2 u_select[11];      // seed 7.3: the share of its width a class keeps, clamp(x / d - y, 0, 1) (SelectionFade)

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
flat out float v_dash_m;        // a piece in a tunnel: the dash period along the route, metres (0: solid)
#endif

// A least width on screen, beyond seed 3.6.3's distance scaling, which does not see the viewing
// angle: far roads seen at a grazing angle are foreshortened across to less than a pixel, and
// without multisampling they break up into dashes. Where the fill's projected width at an end
// falls below u_min_width.x pixels, the quad's upper side there moves up on screen,
// perpendicular to the road's screen direction, until the fill has that width; the casing grows
// in proportion. Upwards only: with the camera upright over a height field, the terrain seen
// just above a point of the ground lies at least as far away, so the road's depth wins there;
// below, it lies in front and would hide the widened pixels. Only across: the caps keep their
// length along the road, so a dead end does not stick out further.

// At one end: the road's screen direction turned upwards (x, y) and how far up its +n side
// lies on screen per metre (z, pixels; negative where +n lies below).
vec3 screenAcross(vec3 p, vec2 t, vec2 n) {
    mat4 m = u_view_projection;
    float keep = 1.0 - u_scale.z;
    // The view-space scale (seed 3.6.2) in clip space: (keep v, 1) = keep (v, 1) + (1 - keep) (0, 0, 0, 1).
    vec4 c = keep * (m * vec4(p, 1.0)) + (1.0 - keep) * u_projection[3];
    if (c.w <= 0.0) return vec3(0.0);
    // Derivatives on screen (pixels per metre) along t, across n and up.
    vec4 ct = keep * (t.x * m[0] + t.y * m[1]);
    vec4 cn = keep * (n.x * m[0] + n.y * m[1]);
    vec4 cu = keep * m[2];
    vec2 to_px = 0.5 * u_min_width.yz / (c.w * c.w);
    vec2 st = (ct.xy * c.w - c.xy * ct.w) * to_px;
    vec2 sn = (cn.xy * c.w - c.xy * cn.w) * to_px;
    vec2 su = (cu.xy * c.w - c.xy * cu.w) * to_px;
    float along = length(st);
    if (along < 1e-6) return vec3(0.0);  // seen end-on: its width on screen is its true one
    vec2 across = vec2(-st.y, st.x) / along;
    if (dot(su, across) < 0.0) across = -across;
    return vec3(across, dot(sn, across));
}

// The clip-space offset per unit w of the corner on side `side` at the end `at` (0: p0, 1: p1).
// One side is the upper one along the whole piece, the one that is upper where the road is seen
// widest: a piece that passes edge-on (crossing the eye's height on a slope) would otherwise
// twist, its widened side changing from one end to the other, and pinch to nothing in between.
// At an end where that side lies below, it moves up past the other side by the least width.
vec2 widening(float at, float side, vec2 t, vec2 n, float fill_width, float width, float least_px) {
    vec3 e0 = screenAcross(a_p0, t, n), e1 = screenAcross(a_p1, t, n);
    float top = (abs(e0.z) >= abs(e1.z) ? e0.z : e1.z) >= 0.0 ? 1.0 : -1.0;
    if (side != top) return vec2(0.0);
    vec3 e = at < 0.5 ? e0 : e1;
    float up = 0.5 * fill_width * top * e.z;  // this side's height above the centre line, pixels
    if (least_px - 2.0 * abs(up) <= 0.0) return vec2(0.0);  // wide enough here
    // From up to (the other side, -up) + the least width. The casing keeps its share.
    float shift = least_px - 2.0 * up;
    return e.xy * (shift * width / fill_width) / (0.5 * u_min_width.yz);
}

void main() {
    int cls = int(a_class + 0.5);
    float width = u_route == 1 ? u_route_width : u_width[cls];
    if (u_pass == 0 && u_route == 0 && u_casing[cls] <= 0.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // no casing for this class: clipped away
        return;
    }
    float fill_width = width;
    if (u_pass == 0) width += 2.0 * (u_route == 1 ? u_route_casing_m : u_casing[cls]);
    // seed 3.6.3: distance-based width scaling beyond a threshold.
    vec3 mid = 0.5 * (a_p0 + a_p1);
    float dist = length((u_view * vec4(mid, 1.0)).xyz);
    // A class left out of distant views (seed 7.3) fades out by narrowing to nothing, its least
    // width too: road_style.h SelectionFade, at the piece's middle as RoadPass::cull measures it.
    float keep = u_route == 1 ? 1.0 : clamp(u_select[cls].x / max(dist, 1e-6) - u_select[cls].y, 0.0, 1.0);
    if (keep <= 0.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // left out: clipped away
        return;
    }
    float scale = keep * clamp(dist / u_scale.x, 1.0, u_scale.y);
    width *= scale;
    fill_width *= scale;

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
    // A route piece in a tunnel (a_class 1: RoutePiece::tunnel) is dashed: dash and gap two
    // route widths each, the width's distance scale rounded down to a power of two so that the
    // pattern keeps its phase between neighbouring pieces.
    v_dash_m = u_route == 1 && a_class > 0.5 ? 4.0 * u_route_width * exp2(floor(log2(max(scale, 1.0)))) : 0.0;
    // Dashed, the distance runs on over the caps, so that where two pieces' quads overlap both
    // put a dash at the same place.
    if (v_dash_m > 0.0) v_measure += sx * reach * 0.5 * width * (a_measure.y - a_measure.x) / max(len, 1e-6);
#endif
    if (u_route == 1) v_color = u_pass == 0 ? u_route_casing : u_route_color;
    else v_color = u_pass == 0 ? u_casing_color[cls] : u_fill[cls];
    vec4 view_pos = u_view * vec4(pos, 1.0);
    // seed 3.6.2: scale in view space by (1 - alpha) against z-fighting; unlike a world-space
    // offset this does not make roads hover when seen from close by.
    view_pos.xyz *= (1.0 - u_scale.z);
    gl_Position = u_projection * view_pos;
    if (u_min_width.x > 0.0) gl_Position.xy += widening(sx < 0.0 ? 0.0 : 1.0, sy, t, n, fill_width, width, keep * u_min_width.x) * gl_Position.w;
}
