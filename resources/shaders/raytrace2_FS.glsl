#version 330 core
//#INCLUDE raymarch.shl
//#INSERT raymarch
//#INCLUDE labels.shl
//#INSERT labels

uniform sampler2D u_entry;  // pass 1: texture-space entry point, alpha 1 where a front face was drawn
uniform vec3 u_eye;
uniform int u_debug_samples;

in vec3 v_world;
out vec4 frag_color;

void main() {
    vec4 entry = texelFetch(u_entry, ivec2(gl_FragCoord.xy), 0);
    vec3 a = entry.a > 0.5 ? entry.xyz : to_texture(u_eye);
    vec3 b = to_texture(v_world);
    vec3 dir = normalize(v_world - u_eye);
    float at;
    vec3 colour = with_planes(with_labels(trace(a, b, dir, at), a, b, dir, at), a, b, at);
    frag_color = u_debug_samples == 1 ? vec4(samples_taken, 0.0, 0.0, 1.0) : vec4(colour, 1.0);
}
