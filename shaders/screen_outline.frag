// seed 3.6.3 "Outlines": edge strength = local maximum of road intensity in a 3x3 neighbourhood
// minus the intensity here, blended dark over the scene. The 3x3 maximum is taken from four
// bilinear fetches at the diagonal half-texel offsets: each averages a 2x2 block and together
// they cover the 3x3 neighbourhood, so a road anywhere around shows up (scaled back to [0, 1]).
in vec2 v_uv;

uniform sampler2D u_road_mask;  // linear filtering
uniform vec3 u_outline_color;
uniform float u_strength;

out vec4 o_color;

void main() {
    vec2 texel = 1.0 / vec2(textureSize(u_road_mask, 0));
    float here = texture(u_road_mask, v_uv).r;
    float m = max(max(texture(u_road_mask, v_uv + vec2(-0.5, -0.5) * texel).r,
                      texture(u_road_mask, v_uv + vec2(0.5, -0.5) * texel).r),
                  max(texture(u_road_mask, v_uv + vec2(-0.5, 0.5) * texel).r,
                      texture(u_road_mask, v_uv + vec2(0.5, 0.5) * texel).r));
    float edge = clamp(min(4.0 * m, 1.0) - here, 0.0, 1.0) * u_strength;
    if (edge <= 0.0) discard;
    o_color = vec4(u_outline_color, edge);
}
