// Terrain shading: hypsometric tint, replaced by the tile's land-cover raster where it has
// coverage, times relief shading; aerial perspective towards the horizon. The land-cover
// texture is the pluggable input (synthetic orthoimages later replace it).
in vec3 v_normal;
in vec2 v_uv;
in float v_height;
in float v_distance;

uniform sampler2D u_land_cover;
uniform vec3 u_light_dir;
uniform vec3 u_sky_color;
uniform vec2 u_fog_range;
uniform float u_brightness;  // 1 by day, lower at night

layout(location = 0) out vec4 o_color;

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

// Analytical relief shading after Jenny (seed 6.7.4): Lambert shading whose light azimuth turns
// locally towards the slope's aspect, so ridges running parallel to the light stay readable;
// flat land keeps a fixed mid tone instead of the Lambert value; contrast grows with height
// (aerial perspective: the valleys recede, the peaks stand out).
float reliefShade(vec3 n, float h) {
    float slope = length(n.xy);
    vec2 light_xy = normalize(u_light_dir.xy);
    float light_az = atan(light_xy.y, light_xy.x);
    float aspect = slope > 1e-4 ? atan(-n.y, -n.x) : light_az;  // downhill direction
    float az = light_az + 0.35 * sin(2.0 * (aspect - light_az));  // local light rotation
    vec3 l = normalize(vec3(cos(az) * length(u_light_dir.xy), sin(az) * length(u_light_dir.xy), u_light_dir.z));
    float lambert = max(dot(n, l), 0.0);
    float flat_tone = 0.85;
    float shade = mix(flat_tone, lambert, smoothstep(0.02, 0.25, slope));
    float contrast = mix(0.8, 1.25, clamp((h - 800.0) / 2000.0, 0.0, 1.0));
    return clamp(0.72 + (shade - 0.72) * contrast, 0.0, 1.2);
}

void main() {
    vec3 n = normalize(v_normal);
    vec4 cover = texture(u_land_cover, v_uv);
    vec3 base = mix(hypsometricTint(v_height), cover.rgb, cover.a);
    float sky = 0.5 + 0.5 * n.z;
    vec3 color = base * (0.25 * sky + 0.85 * reliefShade(n, v_height)) * u_brightness;
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, v_distance);
    o_color = vec4(mix(color, u_sky_color, fog * 0.85), 1.0);
}
