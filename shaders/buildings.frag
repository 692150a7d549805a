in vec3 v_normal;
in vec3 v_color;
in float v_distance;

uniform vec3 u_light_dir;
uniform vec3 u_sky_color;
uniform vec2 u_fog_range;
uniform float u_brightness;

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_road;  // buildings hide roads: no outline on them

void main() {
    vec3 n = normalize(v_normal);
    float lambert = max(dot(n, u_light_dir), 0.0);
    vec3 color = v_color * (0.45 + 0.6 * lambert) * u_brightness;
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, v_distance);
    o_color = vec4(mix(color, u_sky_color, fog * 0.85), 1.0);
    o_road = vec4(0.0);
}
