#version 330 core

uniform sampler2D u_current;   // this frame's cloud buffer
uniform sampler2D u_history;   // the last TAA output, same view
uniform int u_history_valid;
uniform float u_weight;        // this frame's share: 1 / frames so far, at least 1/16

out vec4 out_clouds;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 current = texelFetch(u_current, pixel, 0);
    if (u_history_valid == 0) {
        out_clouds = current;
        return;
    }
    // clamped to the box of this frame's 3x3 neighbourhood: what the wind moved away does not linger
    ivec2 last = textureSize(u_current, 0) - 1;
    vec4 lo = vec4(1e30), hi = vec4(-1e30);
    for (int y = -1; y <= 1; y++) {
        for (int x = -1; x <= 1; x++) {
            vec4 v = texelFetch(u_current, clamp(pixel + ivec2(x, y), ivec2(0), last), 0);
            lo = min(lo, v);
            hi = max(hi, v);
        }
    }
    out_clouds = mix(clamp(texelFetch(u_history, pixel, 0), lo, hi), current, u_weight);
}
