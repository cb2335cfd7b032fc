#version 330 core
// One vertex per chunk of a flake's outline; the flake itself comes per instance.
in vec3 in_flake;  // centre x, y and circumradius

out vec3 vs_flake;
flat out int vs_chunk;

void main() {
    vs_flake = in_flake;
    vs_chunk = gl_VertexID;
}
