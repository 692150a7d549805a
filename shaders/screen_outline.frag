// seed 3.6.3 "Outlines": edge strength = local maximum of road intensity in a 3x3 neighbourhood
// minus the intensity here, blended dark over the scene. Unfiltered texel fetches: on llvmpipe a
// bilinear fetch costs about four of them.
uniform sampler2D u_road_mask;
uniform vec3 u_outline_color;
uniform float u_strength;

out vec4 o_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 hi = textureSize(u_road_mask, 0) - 1;
    float here = texelFetch(u_road_mask, p, 0).r;
    float m = 0.0;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            m = max(m, texelFetch(u_road_mask, clamp(p + ivec2(dx, dy), ivec2(0), hi), 0).r);
        }
    }
    // No discard: an edge of 0 blends to no change.
    o_color = vec4(u_outline_color, clamp(m - here, 0.0, 1.0) * u_strength);
}
