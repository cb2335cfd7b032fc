#version 330 core
//#INCLUDE clouds.shl
//#INSERT clouds
//#INCLUDE clouds_reproject.shl
//#INSERT reproject

uniform ivec2 u_buffer;
uniform sampler2D u_current;   // this frame's cloud buffer
uniform sampler2D u_history;   // the last TAA output (clamp to edge)
uniform int u_history_valid;
uniform float u_weight;        // this frame's share: 1 / frames so far, at least 1/16

out vec4 out_clouds;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 current = texelFetch(u_current, pixel, 0);
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(u_buffer) * 2.0 - 1.0;
    vec2 uv;
    if (u_history_valid == 0 || !reproject(ray_dir(ndc), uv)) {
        out_clouds = current;
        return;
    }
    vec4 lo, hi;
    neighbourhood(u_current, pixel, lo, hi);
    out_clouds = mix(clamp(texture(u_history, uv), lo, hi), current, u_weight);
}
