#version 330 core
// A light's quad: uv 0..1 spans its lit area; positions are relative to the light's centre so that
// world coordinates near 1e6 keep their precision (the CPU subtracts in double).
in vec2 in_uv;
uniform mat2 u_quad;        // R(rotation) * diag(scale)
uniform vec2 u_origin;      // the light's centre in uv
uniform vec2 u_scale;       // world -> clip, y sign included
uniform vec2 u_light_clip;  // the light's centre in clip space
out vec2 v_uv;
out vec2 v_rel;

void main() {
    v_uv = in_uv;
    v_rel = u_quad * (in_uv - u_origin);
    gl_Position = vec4(u_scale * v_rel + u_light_clip, 0.0, 1.0);
}
