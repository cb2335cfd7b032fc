#version 330 core
in vec4 in_position;  // world space, w = 1
uniform mat4 u_view_proj;  // the light's view of one face
out vec3 v_world;

void main() {
    gl_Position = u_view_proj * in_position;
    v_world = in_position.xyz;
}
