#version 330 core
// The 3D scene's triangles (app/gl/lights3d/meshes.py): world space, w = 1.
in vec4 in_position;
in vec3 in_normal;  // the corner's shading normal
in vec3 in_face;    // the triangle's geometric normal (the same at its three corners)
uniform mat4 u_view_proj;
invariant gl_Position;  // shadow_volume_VS.glsl's expression and inputs: its caps and casters meet these depths
out vec3 v_world;
out vec3 v_normal;
flat out vec3 v_face;
flat out vec3 v_corner;  // the triangle's third corner (the provoking vertex): a point of its plane, for faces_light

void main() {
    gl_Position = u_view_proj * in_position;
    v_world = in_position.xyz;
    v_normal = in_normal;
    v_face = in_face;
    v_corner = in_position.xyz;
}
