#version 330 core
// The 3D frame's float sums, clamped (the formulas' saturate), copied into the host's framebuffer.
uniform sampler2D u_image;
in vec2 v_ndc;
out vec4 frag_color;

void main() {
    frag_color = vec4(clamp(texture(u_image, v_ndc * 0.5 + 0.5).rgb, 0.0, 1.0), 1.0);
}
