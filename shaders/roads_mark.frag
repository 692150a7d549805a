// Marks (in the stencil buffer, colour writes off) where the screen-space road outlines can be:
// road footprints widened by a margin (MapRenderer, seed 3.6.3 "Outlines").
out vec4 o_color;

void main() {
    o_color = vec4(0.0);
}
