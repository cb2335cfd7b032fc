#version 330 core
in vec3 in_position;  // a corner of the unit box [-1, 1]^3
uniform vec3 u_extent;  // the volume's box: half extents in world units
uniform mat4 u_view_proj;
out vec3 v_world;

void main() {
    v_world = in_position * u_extent;
    gl_Position = u_view_proj * vec4(v_world, 1.0);
}
