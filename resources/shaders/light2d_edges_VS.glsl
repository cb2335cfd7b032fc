#version 330 core
// Seed 000's shadow geometry: every hull edge is a quad, two corners on the edge and two projected to
// infinity (w = 0) away from the light; the scissor clips them. Positions are relative to the light.
in vec2 in_a;
in vec2 in_b;
in vec2 in_s;             // x: which end (0 = A, 1 = B); y: 1 = projected away
uniform float u_radius;   // penumbra: the emitting disc; hard: unused
uniform vec2 u_emit;      // hard: the emitting point (a jittered sample of the disc)
uniform bool u_soft;
uniform bool u_cover;     // the exact method's cover: every edge, from the disc's outer tangent points
uniform bool u_umbra;     // ... and each edge's own umbra, between its inner tangents (drawn nearer)
uniform vec2 u_scale;
uniform vec2 u_light_clip;
out vec2 v_penumbra_a;
out vec2 v_penumbra_b;
out float v_clip;
out float v_soft;

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

vec2 turned(vec2 v, float angle) {
    return vec2(v.x * cos(angle) - v.y * sin(angle), v.x * sin(angle) + v.y * cos(angle));
}

// The shadow boundary through end `e` of an edge whose other end is `o`: the tangent from e to the
// disc that leaves it on the far side from o (cover), or on o's side (umbra: zero when neither
// tangent does, e.g. an edge pointing at the light).
vec2 tangent_from(vec2 e, vec2 o) {
    vec2 u = normalize(e);
    float angle = asin(min(u_radius / length(e), 1.0));
    vec2 ccw = turned(u, angle), cw = turned(u, -angle);  // the disc is left of ccw, right of cw
    float side = cross2(ccw, o - e);
    if (!u_umbra) return cross2(u, o - e) > 0.0 ? cw : ccw;
    if (side > 0.0) return ccw;
    return cross2(cw, o - e) < 0.0 ? cw : vec2(0.0);
}

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
    } else if (u_cover) {
        // each end's outer boundary: the tangent from the end to the disc, on the far side from the
        // other end; the quads of all edges cover every pixel the hull can shadow (or is)
        vec2 da = tangent_from(in_a, in_b), db = tangent_from(in_b, in_a);
        projected = in_s.y > 0.5 ? vec4(mix(da, db, in_s.x), 0.0, 0.0) : vec4(position, 0.0, 1.0);
        if (u_umbra) {
            vec2 ab = in_b - in_a;
            float den = cross2(da, db);
            float s = cross2(ab, db) / den, t = cross2(ab, da) / den;
            if (da == vec2(0.0) || db == vec2(0.0)) projected = vec4(in_a, 0.0, 1.0);  // no umbra: nothing
            else if (in_s.y > 0.5 && den != 0.0 && s > 0.0 && t > 0.0)
                projected = vec4(in_a + s * da, 0.0, 1.0);  // converging: a triangle, not a bow tie
        }
        v_penumbra_a = v_penumbra_b = vec2(0.0, 1.0);
        v_soft = 0.0;
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
    gl_Position = vec4(u_scale * projected.xy + u_light_clip * projected.w, u_umbra ? -0.5 * projected.w : 0.0,
                       projected.w);
}
