// SPDX-License-Identifier: Apache-2.0
// Shadow-volume roads (seed 3.5): the fragment of a back face of a segment's box (front faces are
// culled) computes, in this one invocation, both intersections of its view ray with the road
// volume: the capped segment (a stadium in xy: a rectangle plus two cylinders along the nadir,
// seed 3.5.1) extruded over [z min, z max]. Computing entry z0 and exit z1 together avoids the
// inconsistent front/back results of seed 3.5.2. The custom two-sided depth test z0 < z_t < z1
// against the terrain depth z_t (written by terrain_tile.frag into a secondary target) keeps
// exactly the pixels where the road volume meets the terrain: pixel-exact draping on any DEM.
in vec3 v_pos;
flat in vec4 v_segment;
flat in vec4 v_volume;          // height above the plane min, max, radius of the box, unscaled road radius
flat in vec3 v_plane;           // z = h0 + g . (xy - p0)
flat in int v_class;

uniform highp sampler2D u_terrain_depth;  // view depth of the terrain per pixel, 0 where none
uniform vec3 u_eye;             // camera position, tile-local metres
uniform vec3 u_forward;         // unit viewing direction
uniform vec3 u_depth;           // projection P[2][2], P[3][2], relative pull towards the camera
uniform vec3 u_fill[11];
uniform vec3 u_casing_color[11];
uniform int u_pass;
uniform vec3 u_scale;           // threshold m, max scale, unused
uniform vec2 u_select[11];      // seed 7.3: the share of its width a class keeps, clamp(x / d - y, 0, 1) (SelectionFade)

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_road;  // road intensity for the screen-space outlines (seed 3.6.3)

const float kFar = 1e30;

// Ray parameters where lo <= o + t * d <= hi.
vec2 slab(float o, float d, float lo, float hi) {
    if (abs(d) < 1e-20) return (o >= lo && o <= hi) ? vec2(-kFar, kFar) : vec2(kFar, -kFar);
    float a = (lo - o) / d, b = (hi - o) / d;
    return vec2(min(a, b), max(a, b));
}

// seed 3.5.1: the ray against the cap cylinder (axis along the nadir) is a 2D ray-circle test:
// (v.v) t^2 + 2 (v.c) t + (c.c - r^2) = 0 with c = O - C. The discriminant is written as
// (v.v) r^2 - (v x c)^2, which equals (v.c)^2 - (v.v)(c.c - r^2) without its cancellation.
vec2 circle(vec2 o, vec2 v, vec2 center, float r) {
    vec2 c = o - center;
    float vv = dot(v, v);
    if (vv < 1e-20) return dot(c, c) <= r * r ? vec2(-kFar, kFar) : vec2(kFar, -kFar);
    float cross_vc = v.x * c.y - v.y * c.x;
    float disc = vv * r * r - cross_vc * cross_vc;
    if (disc <= 0.0) return vec2(kFar, -kFar);  // misses or grazes the cap
    float s = sqrt(disc);
    float b = dot(v, c);
    return vec2((-b - s) / vv, (-b + s) / vv);
}

void main() {
    // The view ray through this pixel, parametrised by view depth: point(z) = eye + z * dir.
    vec3 ray = v_pos - u_eye;
    vec3 dir = ray / dot(ray, u_forward);
    vec2 p0 = v_segment.xy, p1 = v_segment.zw;
    float zt = texelFetch(u_terrain_depth, ivec2(gl_FragCoord.xy), 0).r;
    if (zt <= 0.0) discard;  // no terrain here
    // seed 3.6.3: the width scale of the terrain point this pixel shows (continuous along the road).
    float dist = zt * length(dir);
    float r = min(v_volume.w * clamp(dist / u_scale.x, 1.0, u_scale.y), v_volume.z);
    // seed 7.3 (road_style.h SelectionFade): a class left out of distant views narrows to
    // nothing, here per pixel.
    r *= clamp(u_select[v_class].x / max(dist, 1e-6) - u_select[v_class].y, 0.0, 1.0);
    if (r <= 0.0) discard;
    // Cheap rejection first, with a little slack so the exact test below decides: the terrain
    // point of this pixel must be near the segment and inside the height range. (A SIMD software
    // rasterizer skips the rest for blocks of pixels that all leave here.)
    vec3 terrain = u_eye + zt * dir;
    vec2 seg_d = p1 - p0;
    vec2 q = terrain.xy - p0;
    vec2 foot = q - clamp(dot(q, seg_d) / dot(seg_d, seg_d), 0.0, 1.0) * seg_d;
    float slack = 0.02 * r + 0.05;
    float above = terrain.z - v_plane.x - dot(v_plane.yz, q);
    if (dot(foot, foot) > (r + slack) * (r + slack) || above < v_volume.x - slack || above > v_volume.y + slack) {
        discard;
    }

    // Entry and exit of the stadium prism (convex: the union of its three parts' intervals).
    vec2 seg = p1 - p0;
    float len = length(seg);
    vec2 t = seg / len;
    vec2 n = vec2(-t.y, t.x);
    vec2 rel = u_eye.xy - p0;
    vec2 along = slab(dot(rel, t), dot(dir.xy, t), 0.0, len);
    vec2 across = slab(dot(rel, n), dot(dir.xy, n), -r, r);
    vec2 hit = vec2(max(along.x, across.x), min(along.y, across.y));
    vec2 cap0 = circle(u_eye.xy, dir.xy, p0, r);
    vec2 cap1 = circle(u_eye.xy, dir.xy, p1, r);
    vec2 stadium = vec2(kFar, -kFar);
    if (hit.x < hit.y) stadium = hit;
    if (cap0.x < cap0.y) stadium = vec2(min(stadium.x, cap0.x), max(stadium.y, cap0.y));
    if (cap1.x < cap1.y) stadium = vec2(min(stadium.x, cap1.x), max(stadium.y, cap1.y));
    // Top and bottom of the box (seed 3.5.1: the volume is bounded by the terrain's heights; here
    // two planes parallel to the terrain's local slope): the ray's height above the plane is
    // linear in the depth too.
    vec2 height = slab(u_eye.z - v_plane.x - dot(v_plane.yz, rel), dir.z - dot(v_plane.yz, dir.xy), v_volume.x, v_volume.y);
    float z0 = max(stadium.x, height.x);
    float z1 = min(stadium.y, height.y);

    // seed 3.5.2: custom two-sided depth test against the terrain depth.
    if (!(z0 < zt && zt < z1)) discard;

    vec3 color = u_pass == 0 ? u_casing_color[v_class] : u_fill[v_class];
    o_color = vec4(color, 1.0);
    o_road = vec4(1.0);
    // The road lies on the terrain point at depth zt: use its depth (pulled a little towards the
    // camera, above the depth buffer's rounding) so buildings in front still hide it.
    float z = zt * (1.0 - u_depth.z);
    gl_FragDepth = clamp(0.5 * (-u_depth.x + u_depth.y / z) + 0.5, 0.0, 1.0);
}
