#version 330 core
in vec2 in_pixel;   // origin top left, y down
in vec4 in_colour;
uniform vec2 u_size;
out vec4 v_colour;

void main() {
    gl_Position = vec4(in_pixel.x / u_size.x * 2.0 - 1.0, 1.0 - in_pixel.y / u_size.y * 2.0, 0.0, 1.0);
    v_colour = in_colour;
}
