#version 330 core
//#INCLUDE clouds.shl
//#INSERT clouds

uniform ivec2 u_buffer;  // the cloud buffer's size
uniform int u_stride;    // 1, or 4: this texel traces buffer pixel texel * 4 + u_phase
uniform ivec2 u_phase;

layout(location = 0) out vec4 out_clouds;
layout(location = 1) out vec4 out_lookups;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy) * u_stride + u_phase;
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(u_buffer) * 2.0 - 1.0;
    vec3 d = ray_dir(ndc);
    vec4 clouds = march(u_camera, d, pixel);
    out_clouds = aerial_perspective(clouds, d, cloud_depth);
    out_lookups = vec4(lookups, 0.0, 0.0, 1.0);
}
