#version 330 core
//#INCLUDE clouds.shl
//#INSERT clouds

uniform vec2 u_size;            // the output's size
uniform sampler2D u_clouds;     // the cloud buffer, premultiplied (linear filtering, clamp to edge)
uniform sampler2D u_lookups;    // its texture lookups per pixel (nearest)
uniform int u_debug;            // 1: lookups per pixel, black 0 .. white 1000; 2: this pass's lookups, raw

out vec4 frag_color;

void main() {
    vec2 uv = gl_FragCoord.xy / u_size;
    vec3 d = ray_dir(uv * 2.0 - 1.0);
    float cos_theta = dot(d, u_sun_dir);
    vec4 low = texture(u_clouds, uv);
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
