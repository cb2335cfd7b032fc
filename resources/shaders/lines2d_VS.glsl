#version 330 core
in vec2 in_world;
uniform vec2 u_scale;  // world -> clip
uniform vec2 u_offset;

void main() {
    gl_Position = vec4(in_world * u_scale + u_offset, 0.0, 1.0);
}
