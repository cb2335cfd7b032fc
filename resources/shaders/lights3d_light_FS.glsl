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
uniform bool u_facing_test;  // a shadowed light reaches only faces turned to it (faces_light: their plane)
uniform bool u_reach_mask;   // the debug view: white where the light lights the pixel, instead of its light

in vec3 v_world;
in vec3 v_normal;
flat in vec3 v_face;
flat in vec3 v_corner;
out vec4 frag_color;

void main() {
    vec3 L;
    float katt = attenuation(v_world, L);
    float facing = dot(v_face, L);
    if (katt <= 0.0 || (u_facing_test && !faces_light(v_face, v_corner)))
        discard;
    float visibility = map_visibility(v_world, facing);
    if (u_reach_mask) {
        frag_color = vec4(vec3(visibility >= 0.5 ? 1.0 : 0.0), 0.0);  // added to the debug view's black
        return;
    }
    vec3 N = normalize(v_normal);
    vec3 V = normalize(u_eye - v_world);
    float n_dot_l = dot(N, L);
    vec3 H = L + V;
    H = H / max(length(H), 1e-30);  // L = -V: H = 0, as the reference's (N.L < 0 there: no specular)
    float specular = n_dot_l > 0.0 ? u_specular * pow(clamp(dot(N, H), 0.0, 1.0), u_shininess) : 0.0;
    float lit = katt * visibility;
    frag_color = vec4(lit * (u_albedo * clamp(n_dot_l, 0.0, 1.0) + specular) * u_light_colour, 0.0);
}
