#version 330 core
in vec3 in_position;  // a corner of the box, world units
uniform mat4 u_view_proj;
out vec3 v_world;

void main() {
    v_world = in_position;
    gl_Position = u_view_proj * vec4(in_position, 1.0);
}
