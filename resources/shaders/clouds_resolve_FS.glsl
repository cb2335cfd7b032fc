#version 330 core
//#INCLUDE clouds.shl
//#INSERT clouds
//#INCLUDE clouds_reproject.shl
//#INSERT reproject

uniform ivec2 u_buffer;
uniform ivec2 u_phase;          // the pixel of each 4x4 block traced this frame
uniform sampler2D u_fresh;      // this frame's traced pixels, one per block
uniform sampler2D u_fresh_lookups;
uniform sampler2D u_history;    // the last frame's resolved buffer (clamp to edge)
uniform int u_history_valid;    // 0 after anything but the camera's turn changed: trace everything
uniform int u_turned;           // the camera turned since the last frame: clamp reprojected values

layout(location = 0) out vec4 out_clouds;
layout(location = 1) out vec4 out_lookups;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (pixel % 4 == u_phase) {
        out_clouds = texelFetch(u_fresh, pixel / 4, 0);
        out_lookups = texelFetch(u_fresh_lookups, pixel / 4, 0);
        return;
    }
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(u_buffer) * 2.0 - 1.0;
    vec3 d = ray_dir(ndc);
    vec2 uv;
    if (u_history_valid == 1 && reproject(d, uv)) {
        vec4 last = texture(u_history, uv);
        if (u_turned == 1) {  // reject what this frame's traced neighbours say cannot be there
            vec4 lo, hi;
            neighbourhood(u_fresh, pixel / 4, lo, hi);
            last = clamp(last, lo, hi);
        }
        out_clouds = last;
        out_lookups = vec4(0.0, 0.0, 0.0, 1.0);
    } else {
        out_clouds = march(u_camera, d, pixel);
        out_lookups = vec4(lookups, 0.0, 0.0, 1.0);
    }
}
