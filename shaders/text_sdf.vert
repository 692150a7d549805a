// SPDX-License-Identifier: Apache-2.0
// SDF label text (seed 4.5.2): one instance per glyph quad, a 4-vertex strip per instance.
// Screen mode: anchor in pixels (origin top left, y down). World mode (seed 5.2.1): the text
// lies in a plane of the scene through the anchor, spanned by the baseline direction and the
// glyphs' up direction, and is projected like the rest of the world (foreshortened with
// distance, depth-tested); the caller fades out text that would be too small to read.

layout(location = 0) in vec4 a_rect;     // quad corners p0.xy, p1.xy: px at size_px, y down
layout(location = 1) in vec4 a_tex;      // atlas texels t0.xy, t1.xy
layout(location = 2) in vec4 a_anchor;   // screen: x, y px, 0, angle; world: text center x, y, z, 0
layout(location = 3) in vec4 a_params;   // screen: scale, size_px, alpha, 0; world: em metres, size_px, alpha, 0
layout(location = 4) in vec4 a_fill;
layout(location = 5) in vec4 a_outline;
layout(location = 6) in vec4 a_halo;
layout(location = 7) in vec4 a_widths;   // outline px, halo px (at scale 1), 0, 0
layout(location = 8) in vec4 a_right;    // world: unit baseline direction, 0
layout(location = 9) in vec4 a_up;       // world: unit up direction of the glyphs, 0

uniform vec2 u_viewport;          // target size, px
uniform vec2 u_atlas_size;        // texels
uniform float u_spread_em;        // atlas spread / base em: SDF range in em
uniform int u_world;              // 0 screen, 1 world
uniform mat4 u_view_projection;   // world mode
uniform float u_focal_y;          // projection[1][1] (world mode)

out vec2 v_uv;
out float v_dist_scale;           // px on screen per unit of (sdf - 0.5)
flat out vec4 v_fill;
flat out vec4 v_outline;
flat out vec4 v_halo;
flat out vec2 v_widths;           // outline, halo px on screen
flat out float v_alpha;

void main() {
    vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));
    vec2 local = mix(a_rect.xy, a_rect.zw, corner);
    v_uv = mix(a_tex.xy, a_tex.zw, corner) / u_atlas_size;
    float size_px = a_params.y;
    float scale = a_params.x;
    if (u_world == 1) {
        // Quad corners are px at size_px, y down: metres in the text's plane.
        float metres_per_px = a_params.x / size_px;
        vec3 p = a_anchor.xyz + (a_right.xyz * local.x - a_up.xyz * local.y) * metres_per_px;
        vec4 clip = u_view_projection * vec4(p, 1.0);
        gl_Position = clip;
        // The em size on screen at this corner sets the distance field's scale (outline, halo,
        // antialiasing in screen pixels).
        float w = max(clip.w, 1e-4);
        scale = a_params.x * u_focal_y * 0.5 * u_viewport.y / w / size_px;
    } else {
        float c = cos(a_anchor.w);
        float s = sin(a_anchor.w);
        vec2 off = local * scale;
        off = vec2(c * off.x - s * off.y, s * off.x + c * off.y);  // clockwise on a y-down screen
        vec2 px = a_anchor.xy + off;
        gl_Position = vec4(px.x / u_viewport.x * 2.0 - 1.0, 1.0 - px.y / u_viewport.y * 2.0, 0.0, 1.0);
    }
    float em = size_px * scale;
    v_dist_scale = 2.0 * u_spread_em * em;
    // Outline and halo must stay inside the stored distance range (spread) of the glyph quad.
    float reach = max(u_spread_em * em - 1.0, 0.0);
    float outline = min(a_widths.x * scale, reach);
    v_widths = vec2(outline, min(a_widths.y * scale, reach - outline));
    v_fill = a_fill;
    v_outline = a_outline;
    v_halo = a_halo;
    v_alpha = a_params.z;
}
