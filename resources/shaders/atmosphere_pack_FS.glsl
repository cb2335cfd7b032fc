#version 330 core

// The atlas: each table's texels at its region (x, y, width, height), nothing elsewhere.
uniform sampler2D u_transmittance;
uniform sampler2D u_multiscatter;
uniform sampler2D u_sky_view;
uniform vec4 u_transmittance_region;
uniform vec4 u_multiscatter_region;
uniform vec4 u_sky_view_region;

out vec4 out_atlas;

bool inside(vec2 p, vec4 region) {
    return all(greaterThanEqual(p, region.xy)) && all(lessThan(p, region.xy + region.zw));
}

void main() {
    vec2 p = gl_FragCoord.xy;
    if (inside(p, u_transmittance_region)) {
        out_atlas = texelFetch(u_transmittance, ivec2(p - u_transmittance_region.xy), 0);
    } else if (inside(p, u_multiscatter_region)) {
        out_atlas = texelFetch(u_multiscatter, ivec2(p - u_multiscatter_region.xy), 0);
    } else if (inside(p, u_sky_view_region)) {
        out_atlas = texelFetch(u_sky_view, ivec2(p - u_sky_view_region.xy), 0);
    } else {
        out_atlas = vec4(0.0);
    }
}
