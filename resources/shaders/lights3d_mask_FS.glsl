#version 330 core
// A light's shadow-map visibility per pixel (0 in shadow .. 1 lit), for shadow_mask's readback.
//#INCLUDE lights3d.shl
//#INSERT lights3d
//#INCLUDE shadow_map.shl
//#INSERT shadow_map

in vec3 v_world;
in vec3 v_normal;
flat in vec3 v_face;
out vec4 frag_color;

void main() {
    vec3 L;
    attenuation(v_world, L);
    frag_color = vec4(map_visibility(v_world, dot(v_face, L)), 0.0, 0.0, 1.0);
}
