#version 330 core
in vec4 in_position;  // world space; w = 0: a point at infinity, away from the light
uniform mat4 u_view_proj;
invariant gl_Position;  // other programs drawing the scene's depth get the same depths (declare it there too)

void main() {
    gl_Position = u_view_proj * in_position;
}
