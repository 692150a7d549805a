// SPDX-License-Identifier: Apache-2.0
// Terrain heightfield shading: hypsometric tint x relief shading, faded into the sky with
// distance (aerial perspective). Kept as its own stage so land cover and synthetic orthoimages
// can replace the tint (docs/architecture.md: the terrain shading is pluggable).
in vec3 v_normal;
in float v_height;
in float v_distance;

uniform vec3 u_light_dir;   // normalized, towards the light
uniform vec3 u_sky_color;
uniform vec2 u_fog_range;   // start, end in metres

out vec4 o_color;

vec3 hypsometricTint(float h) {
    // Lowland green -> upland olive -> rock brown -> high grey -> snow.
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
    vec3 n = normalize(v_normal);
    float lambert = max(dot(n, u_light_dir), 0.0);
    float sky = 0.5 + 0.5 * n.z;  // hemispheric ambient: flat ground sees more sky
    vec3 color = hypsometricTint(v_height) * (0.25 * sky + 0.85 * lambert);
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, v_distance);
    o_color = vec4(mix(color, u_sky_color, fog * 0.85), 1.0);
}
