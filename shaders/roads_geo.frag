// seed 3.4: the rounded caps are cut analytically out of the quad. In cap-local coordinates
// x_cap = (|x| - 1) / h + 1, y_cap = |y|; inside the cap region (x_cap > 0) a fragment with
// x_cap^2 + y_cap^2 > 1 lies outside the half circle and is discarded.
in vec2 v_local;
in float v_h;
in float v_measure;
flat in int v_class;

uniform vec3 u_fill[11];
uniform vec3 u_casing_color[11];
uniform int u_pass;
uniform int u_route;
uniform vec3 u_route_color;
uniform vec3 u_route_casing;
uniform float u_route_progress;  // metres driven; the part behind is dimmed

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_road;  // road intensity for the screen-space outlines (seed 3.6.3)

void main() {
    float x_cap = (abs(v_local.x) - 1.0) / v_h + 1.0;
    float y_cap = abs(v_local.y);
    if (x_cap > 0.0 && x_cap * x_cap + y_cap * y_cap > 1.0) discard;
    vec3 color;
    if (u_route == 1) {
        color = u_pass == 0 ? u_route_casing : u_route_color;
        if (v_measure < u_route_progress) color = mix(color, vec3(0.6), 0.65);  // already driven
    } else {
        color = u_pass == 0 ? u_casing_color[v_class] : u_fill[v_class];
    }
    o_color = vec4(color, 1.0);
    o_road = vec4(1.0);
}
