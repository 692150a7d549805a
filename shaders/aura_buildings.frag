// Transparency label aura (seed 5.3.3, 5.5.1), with buildings.vert: step 2 draws the buildings
// again offscreen with the inverse depth test: a fragment in front of a label (z_building <
// z_label, the label OOBB depth buffer) is discarded, so what lies behind the label shows
// through. u_inverse = 0 draws them plainly (same shading as buildings.frag).
in vec3 v_normal;
in vec3 v_color;
in float v_distance;

uniform vec3 u_light_dir;
uniform vec3 u_sky_color;
uniform vec2 u_fog_range;
uniform float u_brightness;
uniform int u_inverse;
uniform highp sampler2D u_label_depth;  // window depth of the nearest enlarged label OOBB (1: none)

layout(location = 0) out vec4 o_color;

void main() {
    if (u_inverse == 1 && gl_FragCoord.z < texelFetch(u_label_depth, ivec2(gl_FragCoord.xy), 0).r) discard;
    // Same shading as buildings.frag.
    vec3 n = normalize(v_normal);
    float lambert = max(dot(n, u_light_dir), 0.0);
    vec3 color = v_color * (0.45 + 0.6 * lambert) * u_brightness;
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, v_distance);
    o_color = vec4(mix(color, u_sky_color, fog * 0.85), 1.0);
}
