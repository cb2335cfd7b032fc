#version 330 core
// One light added to the 3D scene (additive blending, depth EQUAL, the stencil keeping shadowed pixels out).
//#INCLUDE lights3d.shl
//#INSERT lights3d
//#INCLUDE shadow_map.shl
//#INSERT shadow_map

uniform vec3 u_albedo;
uniform vec3 u_light_colour;
uniform vec3 u_eye;
uniform float u_shininess;
uniform float u_specular;
uniform bool u_facing_test;  // a shadowed light reaches only faces turned to it (their geometric normal)

in vec3 v_world;
in vec3 v_normal;
flat in vec3 v_face;
out vec4 frag_color;

void main() {
    vec3 L;
    float katt = attenuation(v_world, L);
    float facing = dot(v_face, L);
    if (katt <= 0.0 || (u_facing_test && facing <= 0.0))
        discard;
    vec3 N = normalize(v_normal);
    vec3 V = normalize(u_eye - v_world);
    float n_dot_l = dot(N, L);
    vec3 H = L + V;
    H = H / max(length(H), 1e-30);  // L = -V: H = 0, as the reference's (N.L < 0 there: no specular)
    float specular = n_dot_l > 0.0 ? u_specular * pow(clamp(dot(N, H), 0.0, 1.0), u_shininess) : 0.0;
    float lit = katt * map_visibility(v_world, facing);
    frag_color = vec4(lit * (u_albedo * clamp(n_dot_l, 0.0, 1.0) + specular) * u_light_colour, 0.0);
}
