// Terrain shading: hypsometric tint, replaced by the tile's land-cover raster where it has
// coverage, times relief shading; aerial perspective towards the horizon. The land-cover
// texture is the pluggable input (synthetic orthoimages later replace it).
in vec2 v_uv;
in float v_height;
in float v_distance;
in float v_shade;  // relief shading from the vertex stage

uniform sampler2D u_land_cover;
uniform vec3 u_sky_color;
uniform vec2 u_fog_range;
uniform float u_brightness;  // 1 by day, lower at night

layout(location = 0) out vec4 o_color;
// Shadow-volume roads (seed 3.5.2): the terrain's view-space depth as a secondary target. Only
// stored where a framebuffer binds draw buffer 3 (SvRoads); 1 / gl_FragCoord.w is the clip w,
// i.e. the exact view depth of this fragment, without an extra varying.
layout(location = 3) out vec4 o_terrain_depth;

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

void main() {
    vec4 cover = texture(u_land_cover, v_uv);
    vec3 base = mix(hypsometricTint(v_height), cover.rgb, cover.a);
    vec3 color = base * v_shade * u_brightness;
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, v_distance);
    o_color = vec4(mix(color, u_sky_color, fog * 0.85), 1.0);
    o_terrain_depth = vec4(1.0 / gl_FragCoord.w, 0.0, 0.0, 0.0);
}
