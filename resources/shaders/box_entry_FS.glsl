#version 330 core
uniform vec3 u_extent;
in vec3 v_world;
out vec4 entry;

void main() {
    entry = vec4((v_world * vec3(1.0, -1.0, -1.0) / u_extent + 1.0) * 0.5, 1.0);
}
