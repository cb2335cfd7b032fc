#version 330 core
uniform sampler2D u_image;
in vec2 v_ndc;
out vec4 frag_color;

void main() {
    frag_color = texture(u_image, v_ndc * 0.5 + 0.5);
}
