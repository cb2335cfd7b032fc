#version 330 core
//#INCLUDE clouds.shl
//#INSERT clouds

uniform ivec2 u_buffer;
uniform ivec2 u_phase;          // the pixel of each 4x4 block traced this frame
uniform sampler2D u_fresh;      // this frame's traced pixels, one per block
uniform sampler2D u_fresh_lookups;
uniform sampler2D u_history;    // the last frame's resolved buffer, same view
uniform int u_history_valid;    // 0 after anything changed but the clock: trace every pixel

layout(location = 0) out vec4 out_clouds;
layout(location = 1) out vec4 out_lookups;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (pixel % 4 == u_phase) {
        out_clouds = texelFetch(u_fresh, pixel / 4, 0);
        out_lookups = texelFetch(u_fresh_lookups, pixel / 4, 0);
    } else if (u_history_valid == 1) {
        out_clouds = texelFetch(u_history, pixel, 0);
        out_lookups = vec4(0.0, 0.0, 0.0, 1.0);
    } else {
        vec2 ndc = (vec2(pixel) + 0.5) / vec2(u_buffer) * 2.0 - 1.0;
        out_clouds = march(u_camera, ray_dir(ndc), pixel);
        out_lookups = vec4(lookups, 0.0, 0.0, 1.0);
    }
}
