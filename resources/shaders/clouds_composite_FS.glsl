#version 330 core
//#INCLUDE clouds.shl
//#INSERT clouds
//#INCLUDE clouds_upsample.shl
//#INSERT clouds_upsample

uniform vec2 u_size;            // the output's size
uniform sampler2D u_clouds;     // the cloud buffer, premultiplied
uniform sampler2D u_lookups;    // its state (clouds_upsample.shl): .r texture lookups per texel, .b ground
uniform int u_debug;            // 1: lookups per pixel, black 0 .. white 1000; 2: this pass's lookups, raw

out vec4 frag_color;

// The cloud buffer at this pixel: nothing where the ray meets no clouds; else from the buffer's texels whose rays
// end where this one's does (the ground or the sky).
vec4 clouds_at(vec3 d) {
    float t0, t1, weight;
    if (!cloud_segment(u_camera, d, t0, t1)) return vec4(0.0);
    vec2 q = gl_FragCoord.xy * vec2(textureSize(u_clouds, 0)) / u_size - 0.5;
    vec4 state;
    return upsample(u_clouds, u_lookups, q, ground_ray(u_camera, d) ? 1.0 : 0.0, false, state, weight);
}

void main() {
    vec2 uv = gl_FragCoord.xy / u_size;
    vec3 d = ray_dir(uv * 2.0 - 1.0);
    float cos_theta = dot(d, u_sun_dir);
    vec4 low = clouds_at(d);
    vec4 high = cirrus(u_camera, d, cos_theta);
    vec4 clouds = u_camera.y > R_CIRRUS - PLANET_RADIUS ? low * (1.0 - high.a) + high : high * (1.0 - low.a) + low;
    vec3 colour = clouds.rgb + (1.0 - clouds.a) * background(u_camera, d, cos_theta);  // linear, unclamped
    if (u_debug == 1) {
        frag_color = vec4(vec3(clamp((texture(u_lookups, uv).r + lookups) / 1000.0, 0.0, 1.0)), 1.0);
    } else if (u_debug == 2) {
        frag_color = vec4(lookups, 0.0, 0.0, 1.0);
    } else {
        frag_color = vec4(colour, 1.0);
    }
}
