#version 330 core
// Seed 000's shadow geometry: every hull edge is a quad, two corners on the edge and two projected to
// infinity (w = 0) away from the light; the scissor clips them. Positions are relative to the light.
in vec2 in_a;
in vec2 in_b;
in vec2 in_s;             // x: which end (0 = A, 1 = B); y: 1 = projected away
uniform float u_radius;   // penumbra: the emitting disc; hard: unused
uniform vec2 u_emit;      // hard: the emitting point (a jittered sample of the disc)
uniform bool u_soft;
uniform vec2 u_scale;
uniform vec2 u_light_clip;
out vec2 v_penumbra_a;
out vec2 v_penumbra_b;
out float v_clip;
out float v_soft;

void main() {
    vec2 position = mix(in_a, in_b, in_s.x);
    vec4 projected;
    if (u_soft) {
        // lightOffsetA = L + r (-1, 1) normalize(a1).yx, lightOffsetB = L + r (1, -1) normalize(b1).yx
        vec2 a1 = in_a, b1 = in_b;
        vec2 offset_a = u_radius * vec2(-1.0, 1.0) * normalize(a1).yx;
        vec2 offset_b = u_radius * vec2(1.0, -1.0) * normalize(b1).yx;
        vec2 offset = mix(offset_a, offset_b, in_s.x);
        projected = vec4(position - offset * in_s.y, 0.0, 1.0 - in_s.y);
        // PenumbraA = (projected.xy - A w) * inverse(mat2(lightOffsetA, a1)): +-1 on the two tangent lines
        v_penumbra_a = inverse(mat2(offset_a, a1)) * (projected.xy - in_a * projected.w);
        v_penumbra_b = inverse(mat2(offset_b, b1)) * (projected.xy - in_b * projected.w);
        v_soft = 1.0;
    } else {
        projected = vec4(position - u_emit * in_s.y, 0.0, 1.0 - in_s.y);
        // only edges facing away from the emitter cast (the hull pass decides the hull itself)
        vec2 e = in_b - in_a;
        if (dot(vec2(e.y, -e.x), in_a - u_emit) <= 0.0) projected = vec4(in_a, 0.0, 1.0);
        v_penumbra_a = v_penumbra_b = vec2(0.0, 1.0);
        v_soft = 0.0;
    }
    vec2 e = in_b - in_a;
    v_clip = dot(vec2(e.y, -e.x), projected.xy - position * projected.w);
    gl_Position = vec4(u_scale * projected.xy + u_light_clip * projected.w, 0.0, projected.w);
}
