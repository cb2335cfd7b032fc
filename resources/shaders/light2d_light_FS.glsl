#version 330 core
// Seed 000's light shaders: point, spot and textured, colour = pow(color * a, intensity); the blend
// multiplies by the shadow mask in the destination alpha. With a normal map and a height, N . L too.
in vec2 v_uv;
in vec2 v_rel;
uniform int u_kind;           // 0 point, 1 spot, 2 textured
uniform vec3 u_color;
uniform float u_intensity;
uniform float u_cone;         // spot: half of the cone angle
uniform float u_decay;
uniform sampler2D u_cookie;   // textured: intensity in the green channel
uniform bool u_normals_on;
uniform sampler2D u_normals;  // 1 texel per world unit, repeating
uniform vec2 u_normal_at;     // the light's centre in normal-map texture coordinates (mod 1)
uniform float u_height;
out vec4 frag_color;

void main() {
    float a;
    if (u_kind == 0) {
        a = clamp(1.0 - 2.0 * length(v_uv - 0.5), 0.0, 1.0);
    } else if (u_kind == 1) {
        vec2 v = v_uv - vec2(0.0, 0.5);
        float len = length(v);
        float half_angle = acos(clamp(v.x / max(len, 1e-30), -1.0, 1.0));
        float edge = u_decay == 0.0 ? 1.0 : pow(half_angle / u_cone, u_decay);
        a = clamp(1.0 - len, 0.0, 1.0) * (1.0 - edge) * step(half_angle, u_cone);
    } else {
        a = texture(u_cookie, v_uv).g;
    }
    vec3 base = u_color * a;
    vec3 value = mix(vec3(0.0), pow(max(base, vec3(1e-30)), vec3(u_intensity)), greaterThan(base, vec3(0.0)));
    if (u_normals_on) {
        vec3 n = normalize(texture(u_normals, u_normal_at + v_rel / vec2(textureSize(u_normals, 0))).rgb * 2.0 - 1.0);
        value *= max(dot(n, normalize(vec3(-v_rel, u_height))), 0.0);
    }
    frag_color = vec4(value, 1.0);
}
