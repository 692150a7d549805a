// seed 3.4: the rounded caps are cut analytically out of the quad. In cap-local coordinates
// x_cap = (|x| - 1) / h + 1, y_cap = |y|; inside the cap region (x_cap > 0) a fragment with
// x_cap^2 + y_cap^2 > 1 lies outside the half circle and is discarded.
in vec2 v_local;
in float v_h;
in float v_measure;
flat in vec3 v_color;  // this pass's colour of the road class or the route

uniform int u_route;
uniform float u_route_progress;  // metres driven; the part behind is dimmed

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_road;  // road intensity for the screen-space outlines (seed 3.6.3)

void main() {
    float x_cap = (abs(v_local.x) - 1.0) / v_h + 1.0;
    float y_cap = abs(v_local.y);
    if (x_cap > 0.0 && x_cap * x_cap + y_cap * y_cap > 1.0) discard;
    vec3 color = v_color;
    if (u_route == 1 && v_measure < u_route_progress) color = mix(color, vec3(0.6), 0.65);  // already driven
    o_color = vec4(color, 1.0);
    o_road = vec4(1.0);
}
