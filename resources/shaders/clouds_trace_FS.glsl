#version 330 core
//#INCLUDE clouds.shl
//#INSERT clouds
//#INCLUDE clouds_upsample.shl
//#INSERT clouds_upsample

uniform ivec2 u_buffer;  // the cloud buffer's size
uniform int u_stride;    // 1, or d: this texel traces buffer pixel texel * d + u_phase
uniform ivec2 u_phase;

layout(location = 0) out vec4 out_clouds;
layout(location = 1) out vec4 out_state;  // the buffer's state (clouds_upsample.shl): lookups, traced, ground, depth

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy) * u_stride + u_phase;
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(u_buffer) * 2.0 - 1.0;
    vec3 d = ray_dir(ndc);
    vec4 clouds = march(u_camera, d, pixel);
    out_clouds = aerial_perspective(clouds, d, cloud_depth);
    out_state = vec4(lookups, 1.0, ground_ray(u_camera, d) ? 1.0 : 0.0, light_depth);
}
