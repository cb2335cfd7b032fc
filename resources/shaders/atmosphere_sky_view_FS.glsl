#version 330 core
//#INCLUDE atmosphere.shl
//#INSERT atmosphere

// The sky seen from radius u_camera_radius with the sun at u_sun_mu, per unit sun illuminance: each texel's
// direction marched to the top of the atmosphere or the ground (no light from the ground itself).
uniform sampler2D u_transmittance;
uniform sampler2D u_multiscatter;
uniform float u_camera_radius;
uniform float u_sun_mu;
uniform int u_sky_view_steps;
uniform int u_multiple;  // 0: single scattering only (the tests' comparison with the integral)

out vec4 out_sky;

vec3 transmittance_lut(vec2 uv) { return texture(u_transmittance, uv).rgb; }
vec3 multiscatter_lut(vec2 uv) { return texture(u_multiscatter, uv).rgb; }

void main() {
    vec2 uv = gl_FragCoord.xy / SKY_VIEW_SIZE;
    float r = u_camera_radius;
    float beta, horizon;
    horizon_angles(r, beta, horizon);
    float y = texel_to_unit(uv.y, SKY_VIEW_SIZE.y), x = texel_to_unit(uv.x, SKY_VIEW_SIZE.x);
    float zenith = y < 0.5 ? horizon * (1.0 - (1.0 - 2.0 * y) * (1.0 - 2.0 * y)) : horizon + beta * (2.0 * y - 1.0) * (2.0 * y - 1.0);
    float mu = cos(zenith), cos_azimuth = 1.0 - 2.0 * x * x;
    float nu = sqrt(max(1.0 - mu * mu, 0.0)) * cos_azimuth * sqrt(max(1.0 - u_sun_mu * u_sun_mu, 0.0)) + mu * u_sun_mu;
    vec3 lum, throughput;
    // the table's half says whether the ray meets the ground (float32 cannot tell at the horizon's texels)
    float end = y < 0.5 ? distance_to_top(r, mu) : distance_to_ground(r, mu);
    scatter(r, mu, u_sun_mu, nu, end, u_sky_view_steps, u_multiple == 1, lum, throughput);
    out_sky = vec4(lum, 1.0);
}
