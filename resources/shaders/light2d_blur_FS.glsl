#version 330 core
// One direction of a separable Gaussian blur of a hard shadow mask (what the seed rejects and
// pygame-light2d does), sigma in lightmap pixels.
uniform sampler2D u_mask;
uniform vec2 u_step;
uniform float u_sigma;
out vec4 frag_color;

void main() {
    int reach = int(ceil(3.0 * u_sigma));
    vec2 size = vec2(textureSize(u_mask, 0));
    vec2 at = gl_FragCoord.xy / size;
    float sum = 0.0, weight = 0.0;
    for (int k = -reach; k <= reach; ++k) {
        float w = exp(-0.5 * float(k * k) / (u_sigma * u_sigma));
        sum += w * texture(u_mask, at + float(k) * u_step / size).r;
        weight += w;
    }
    frag_color = vec4(sum / weight);
}
