// SPDX-License-Identifier: Apache-2.0
// Cartographic roads, shadow-volume approach (seed 3.5): every road segment (original polyline
// vertices, no draping pre-process) becomes a box extruded along the nadir, bounded by the height
// range of the terrain under it (seed 3.5.1: not to infinity) and wide enough for both rounded
// caps. Only its back faces are drawn (front-face culling, seed 3.5.2), so each covered pixel runs
// the fragment stage once per segment even with the camera inside the box; roads_sv.frag finds
// where the view ray meets the road volume and the terrain.
layout(location = 0) in vec4 a_segment;  // p0.xy, p1.xy, tile-local metres
layout(location = 1) in vec2 a_z_range;  // terrain height above the plane within a_reach of the segment, metres
layout(location = 2) in float a_class;
layout(location = 3) in float a_reach;
layout(location = 4) in vec3 a_plane;    // z = a_plane.x + a_plane.yz . (xy - p0): follows the terrain

uniform mat4 u_view;
uniform mat4 u_projection;
uniform vec3 u_eye;             // camera position, tile-local metres
uniform float u_width[11];      // fill width per road class, metres
uniform float u_casing[11];     // extra casing width per side, metres (0: none)
uniform int u_pass;             // 0 casing, 1 fill
uniform vec3 u_scale;           // threshold m, max scale, unused
uniform float u_max_slope;      // bound on the terrain slope of the tile (dz / dxy)
uniform vec2 u_select[11];      // seed 7.3: the share of its width a class keeps, clamp(x / d - y, 0, 1) (SelectionFade)

out vec3 v_pos;                 // box surface point, tile-local
flat out vec4 v_segment;        // p0.xy, p1.xy
flat out vec4 v_volume;         // height above the plane min, max, radius of the box, unscaled road radius
flat out vec3 v_plane;
flat out int v_class;

// gl_VertexID is the box corner (an indexed draw, SvRoads::kBoxIndices, so each corner is shaded
// once): bit 0 along the segment (p0 / p1 side), bit 1 across (-n / +n), bit 2 bottom / top.

void main() {
    int cls = int(a_class + 0.5);
    float width = u_width[cls];
    if (u_pass == 0) {
        if (u_casing[cls] <= 0.0) {
            gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // no casing for this class: clipped away
            return;
        }
        width += 2.0 * u_casing[cls];
    }
    vec2 p0 = a_segment.xy, p1 = a_segment.zw;
    // seed 3.6.3: distance-based width scaling beyond a threshold. The fragment stage scales per
    // pixel by the distance of the terrain point; the box holds the widest: the far end's.
    vec3 q0 = vec3(p0, a_plane.x), q1 = vec3(p1, a_plane.x + dot(a_plane.yz, p1 - p0));
    float dist = max(length(q0 - u_eye), length(q1 - u_eye));
    float r_base = 0.5 * width;
    float r = r_base * clamp(dist / u_scale.x, 1.0, u_scale.y);

    // The height range holds for the ground within a_reach of the segment; a wider (scaled)
    // road reaches further, where the terrain can be higher or lower (than the plane) by at most
    // (slope + plane slope) * distance.
    float grow = max(r - a_reach, 0.0) * (u_max_slope + length(a_plane.yz)) + 0.5;
    float z_lo = a_z_range.x - grow, z_hi = a_z_range.y + grow;

    // seed 7.3: roads_sv.frag narrows a class left out of distant views per pixel; a box whose
    // nearest possible terrain point lies where the class is gone (x / d <= y) is clipped away.
    // The terrain it holds lies within r across and [z_lo, z_hi] up of the plane's line q0 q1.
    if (u_select[cls].y > 0.0) {
        float nearest = min(length(q0 - u_eye), length(q1 - u_eye)) - 0.5 * length(q1 - q0) - r - max(abs(z_lo), abs(z_hi));
        if (u_select[cls].x <= u_select[cls].y * nearest) {
            gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
            return;
        }
    }

    vec2 d = p1 - p0;
    float len = length(d);
    vec2 t = len > 1e-4 ? d / len : vec2(1.0, 0.0);
    vec2 n = vec2(-t.y, t.x);
    int corner = gl_VertexID & 7;  // eight vertices per box
    float sx = (corner & 1) != 0 ? 1.0 : -1.0;
    float sy = (corner & 2) != 0 ? 1.0 : -1.0;
    vec2 base = sx < 0.0 ? p0 : p1;
    // seed 3.4 quad Q_i = P +- n' +- t' (with caps), extruded to [z_lo, z_hi] above the plane.
    vec2 xy = base + r * (sx * t + sy * n);
    vec3 pos = vec3(xy, a_plane.x + dot(a_plane.yz, xy - p0) + ((corner & 4) != 0 ? z_hi : z_lo));
    v_pos = pos;
    v_segment = vec4(p0, len > 1e-4 ? p1 : p0 + vec2(1e-4, 0.0));
    v_volume = vec4(z_lo, z_hi, r, r_base);
    v_plane = a_plane;
    v_class = cls;
    gl_Position = u_projection * (u_view * vec4(pos, 1.0));
}
