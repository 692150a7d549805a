// SPDX-License-Identifier: Apache-2.0
// Glowing roads (seed 5.5.2, optional blur): one direction of a separable 9-tap Gaussian
// (sigma about 2 texels of the destination), premultiplied colour. The first pass also
// halves the resolution: u_step is given in source texels.
in vec2 v_uv;

uniform sampler2D u_source;  // linear filtering
uniform vec2 u_step;         // offset between taps, in uv

out vec4 o_color;

void main() {
    const float w[5] = float[5](0.2270270, 0.1945946, 0.1216216, 0.0540541, 0.0162162);
    vec4 sum = texture(u_source, v_uv) * w[0];
    for (int i = 1; i < 5; ++i) {
        sum += texture(u_source, v_uv + float(i) * u_step) * w[i];
        sum += texture(u_source, v_uv - float(i) * u_step) * w[i];
    }
    o_color = sum;
}
