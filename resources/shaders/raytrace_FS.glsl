#version 330 core
//#INCLUDE raymarch.shl
//#INSERT raymarch
//#INCLUDE scalar_modes.shl
//#INSERT scalar_modes
//#INCLUDE labels.shl
//#INSERT labels

uniform mat4 u_inv_view_proj;
uniform vec3 u_eye;
uniform int u_debug_samples;  // 1: output the pixel's texture-sample count instead of a colour

in vec2 v_ndc;
out vec4 frag_color;

void main() {
    vec4 far = u_inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 dir = normalize(far.xyz / far.w - u_eye);
    vec2 span = box_hit(u_eye, dir);
    vec3 colour = u_background;
    if (span.x < span.y) {
        vec3 a = to_texture(u_eye + dir * span.x);
        vec3 b = to_texture(u_eye + dir * span.y);
        float at;
        vec3 traced = SCALAR_MODE == 0 ? trace(a, b, dir, at) : scalar_trace(a, b, dir, at);
        colour = with_planes(with_labels(traced, a, b, dir, at), a, b, at);
    }
    frag_color = u_debug_samples == 1 ? vec4(samples_taken, 0.0, 0.0, 1.0) : vec4(colour, 1.0);
}
