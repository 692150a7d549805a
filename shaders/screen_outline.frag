// seed 3.6.3 "Outlines": the local maximum of road intensity in a 5x5 neighbourhood minus the
// intensity here is the edge strength; blended dark over the scene.
in vec2 v_uv;

uniform sampler2D u_road_mask;
uniform vec3 u_outline_color;
uniform float u_strength;

out vec4 o_color;

void main() {
    ivec2 size = textureSize(u_road_mask, 0);
    ivec2 p = ivec2(v_uv * vec2(size));
    float here = texelFetch(u_road_mask, p, 0).r;
    float m = here;
    for (int dy = -2; dy <= 2; ++dy) {
        for (int dx = -2; dx <= 2; ++dx) {
            ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            m = max(m, texelFetch(u_road_mask, q, 0).r);
        }
    }
    float edge = clamp(m - here, 0.0, 1.0) * u_strength;
    if (edge <= 0.0) discard;
    o_color = vec4(u_outline_color, edge);
}
