#version 330 core
//#INCLUDE atmosphere.shl
//#INSERT atmosphere

// Psi_ms at each (mu_s, r): app.model.clouds.atmosphere.multiple_scattering, the sun's transmittance from its table.
uniform sampler2D u_transmittance;
uniform int u_multiscatter_steps;
uniform int u_multiscatter_directions;  // n: n x n directions over the sphere
uniform vec3 u_ground_albedo;

out vec4 out_multiscatter;

vec3 transmittance_lut(vec2 uv) { return texture(u_transmittance, uv).rgb; }
vec3 multiscatter_lut(vec2 uv) { return vec3(0.0); }  // this pass makes it

void main() {
    vec2 uv = gl_FragCoord.xy / MULTISCATTER_SIZE;
    float mu_s = 2.0 * texel_to_unit(uv.x, MULTISCATTER_SIZE.x) - 1.0;
    float r = max(u_bottom_radius + texel_to_unit(uv.y, MULTISCATTER_SIZE.y) * (u_top_radius - u_bottom_radius),
                  u_bottom_radius + MIN_ALTITUDE);
    float sx = sqrt(max(1.0 - mu_s * mu_s, 0.0));  // the sun at (sx, mu_s, 0)
    int n = u_multiscatter_directions;
    vec3 lum_sum = vec3(0.0), f_sum = vec3(0.0);
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            float theta = 2.0 * ATMO_PI * (float(i) + 0.5) / float(n);
            float mu = 1.0 - 2.0 * (float(j) + 0.5) / float(n);
            float dot_sun = cos(theta) * sqrt(1.0 - mu * mu) * sx + mu * mu_s;
            bool ground = hits_ground(r, mu);
            float end = ground ? distance_to_ground(r, mu) : distance_to_top(r, mu);
            float dt = end / float(u_multiscatter_steps);
            vec3 lum = vec3(0.0), f = vec3(0.0), throughput = vec3(1.0);
            for (int k = 0; k < u_multiscatter_steps; k++) {
                float t = (float(k) + 0.5) * dt;
                float rp = along(r, mu, t);
                vec3 rayleigh, extinction;
                float mie;
                coefficients(rp - u_bottom_radius, rayleigh, mie, extinction);
                vec3 scattering = rayleigh + mie;
                vec3 integral = step_integral(extinction, dt);
                lum += throughput * scattering * sun_transmittance(rp, (r * mu_s + t * dot_sun) / rp) / (4.0 * ATMO_PI)
                       * integral;
                f += throughput * scattering * integral;
                throughput *= exp(-extinction * dt);
            }
            if (ground) {
                float rg = along(r, mu, end);
                float mu_g = (r * mu_s + end * dot_sun) / rg;
                lum += throughput * sun_transmittance(u_bottom_radius, mu_g) * max(mu_g, 0.0) * u_ground_albedo / ATMO_PI;
            }
            lum_sum += lum;
            f_sum += f;
        }
    }
    float count = float(n * n);
    out_multiscatter = vec4(lum_sum / count / (1.0 - f_sum / count), 1.0);
}
