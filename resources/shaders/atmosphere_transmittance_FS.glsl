#version 330 core
//#INCLUDE atmosphere.shl
//#INSERT atmosphere

uniform int u_transmittance_steps;

out vec4 out_transmittance;

vec3 transmittance_lut(vec2 uv) { return vec3(0.0); }  // this pass makes it
vec3 multiscatter_lut(vec2 uv) { return vec3(0.0); }

void main() {
    float r, mu;
    transmittance_params(gl_FragCoord.xy / TRANSMITTANCE_SIZE, r, mu);
    float dt = distance_to_top(r, mu) / float(u_transmittance_steps);
    vec3 tau = vec3(0.0);
    for (int i = 0; i < u_transmittance_steps; i++) {
        vec3 rayleigh, extinction;
        float mie;
        coefficients(along(r, mu, (float(i) + 0.5) * dt) - u_bottom_radius, rayleigh, mie, extinction);
        tau += extinction * dt;
    }
    out_transmittance = vec4(exp(-tau), 1.0);
}
