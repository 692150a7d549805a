// SPDX-License-Identifier: Apache-2.0
// Terrain of one tile: grid + skirts, positions tile-local; the view matrix is relative to the
// tile origin (computed in double on the CPU), so nothing jitters far from the store origin.
#ifndef NAVMAP_COVER_LEVELS
#define NAVMAP_COVER_LEVELS 1  // land-cover levels blended (terrain_tile.frag)
#endif
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec2 a_normal;  // x, y (z >= 0 follows)
// Geomorph targets: the surfaces of the 4 coarser levels at this x, y (parent first), with
// the x, y of their normals (z >= 0 follows).
layout(location = 2) in vec4 a_ancestor_height;
layout(location = 3) in vec4 a_ancestor_normal01;
layout(location = 4) in vec4 a_ancestor_normal23;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform float u_tile_size;
uniform vec3 u_light_dir;
uniform vec2 u_fog_range;
uniform vec3 u_sky_color;
uniform float u_brightness;  // 1 by day, lower at night
// Geomorphing (render/include/navmap/render/terrain_lod.h): per slot j (level L - j to L - j - 1)
// the distances where the morph starts and ends (end <= start: none); the camera's x, y
// tile-local and its vertical distance from the LOD height band.
uniform vec4 u_morph_start;
uniform vec4 u_morph_end;
uniform vec2 u_morph_eye;
uniform float u_morph_eye_dz;

out vec2 v_uv;
#if NAVMAP_COVER_LEVELS > 1
// The land cover morphs with the surface (terrain_tile.frag): the factor of the slot from the
// finest level drawn (u_cover_slot picks slot 0 or 1), then that of slot 1.
uniform vec2 u_cover_slot;
out vec2 v_cover_morph;
#endif
out vec3 v_tint;
out float v_shade;  // relief shading times brightness, times the share of the ground (1 - fog)
out vec3 v_sky;     // aerial perspective: the sky colour times its share

// Analytical relief shading after Jenny (seed 6.7.4), evaluated per vertex (the DEM samples are
// the shading resolution anyway, and llvmpipe pays dearly for per-fragment trigonometry):
// Lambert shading whose light azimuth turns locally towards the slope's aspect, so ridges
// parallel to the light stay readable; flat land keeps a mid tone; contrast grows with height.
float reliefShade(vec3 n, float h) {
    float slope = length(n.xy);
    vec2 light_xy = normalize(u_light_dir.xy);
    float light_az = atan(light_xy.y, light_xy.x);
    float aspect = slope > 1e-4 ? atan(-n.y, -n.x) : light_az;  // downhill direction
    float az = light_az + 0.35 * sin(2.0 * (aspect - light_az));  // local light rotation
    vec3 l = normalize(vec3(cos(az) * length(u_light_dir.xy), sin(az) * length(u_light_dir.xy), u_light_dir.z));
    float lambert = max(dot(n, l), 0.0);
    float shade = mix(0.85, lambert, smoothstep(0.02, 0.25, slope));
    float contrast = mix(0.8, 1.25, clamp((h - 800.0) / 2000.0, 0.0, 1.0));
    return clamp(0.72 + (shade - 0.72) * contrast, 0.0, 1.2);
}

vec3 hypsometricTint(float h) {
    const vec3 c0 = vec3(0.45, 0.60, 0.36);
    const vec3 c1 = vec3(0.62, 0.66, 0.42);
    const vec3 c2 = vec3(0.66, 0.56, 0.42);
    const vec3 c3 = vec3(0.62, 0.60, 0.58);
    const vec3 c4 = vec3(0.96, 0.96, 0.98);
    if (h < 1200.0) return mix(c0, c1, clamp((h - 400.0) / 800.0, 0.0, 1.0));
    if (h < 1900.0) return mix(c1, c2, (h - 1200.0) / 700.0);
    if (h < 2500.0) return mix(c2, c3, (h - 1900.0) / 600.0);
    return mix(c3, c4, clamp((h - 2500.0) / 400.0, 0.0, 1.0));
}

vec3 unpackNormal(vec2 xy) { return vec3(xy, sqrt(max(1.0 - dot(xy, xy), 0.0))); }

void main() {
    // terrain_lod.h: S_L(d) = mix(h_L, S_L-1(d), f_L(d)), from the coarsest level inwards, with
    // the factors of morphFactor()/morphedHeight() in terrain_lod.cpp. The distance is taken as
    // the selection measures boxes, from x, y only, so a skirt vertex morphs with its border vertex.
    vec2 d = a_position.xy - u_morph_eye;
    float dist = sqrt(dot(d, d) + u_morph_eye_dz * u_morph_eye_dz);
    vec4 on = vec4(greaterThan(u_morph_end, u_morph_start));
    vec4 f = on * clamp((dist - u_morph_start) / max(u_morph_end - u_morph_start, vec4(1e-3)), 0.0, 1.0);
    float z = a_ancestor_height.w;
    vec3 n = unpackNormal(a_ancestor_normal23.zw);
    z = mix(a_ancestor_height.z, z, f.w);
    n = mix(unpackNormal(a_ancestor_normal23.xy), n, f.w);
    z = mix(a_ancestor_height.y, z, f.z);
    n = mix(unpackNormal(a_ancestor_normal01.zw), n, f.z);
    z = mix(a_ancestor_height.x, z, f.y);
    n = mix(unpackNormal(a_ancestor_normal01.xy), n, f.y);
    z = mix(a_position.z, z, f.x);
    n = normalize(mix(unpackNormal(a_normal), n, f.x));
    vec3 p = vec3(a_position.xy, z);
    vec4 view_pos = u_view * vec4(p, 1.0);
    float sky = 0.5 + 0.5 * n.z;
    float shade = 0.25 * sky + 0.85 * reliefShade(n, p.z);
    v_uv = a_position.xy / u_tile_size;
#if NAVMAP_COVER_LEVELS > 1
    v_cover_morph = vec2(dot(f.xy, u_cover_slot), f.y);
#endif
    v_tint = hypsometricTint(p.z);
    float fog = 0.85 * smoothstep(u_fog_range.x, u_fog_range.y, length(view_pos.xyz));
    v_shade = shade * u_brightness * (1.0 - fog);
    v_sky = u_sky_color * fog;
    gl_Position = u_projection * view_pos;
}
