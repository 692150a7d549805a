// Terrain of one tile: grid + skirts, positions tile-local; the view matrix is relative to the
// tile origin (computed in double on the CPU), so nothing jitters far from the store origin.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform float u_tile_size;
uniform vec3 u_light_dir;

out vec2 v_uv;
out float v_height;
out float v_distance;
out float v_shade;

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

void main() {
    vec4 view_pos = u_view * vec4(a_position, 1.0);
    vec3 n = normalize(a_normal);
    float sky = 0.5 + 0.5 * n.z;
    v_shade = 0.25 * sky + 0.85 * reliefShade(n, a_position.z);
    v_uv = a_position.xy / u_tile_size;
    v_height = a_position.z;
    v_distance = length(view_pos.xyz);
    gl_Position = u_projection * view_pos;
}
