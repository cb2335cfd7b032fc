#version 330 core
// The exact method's regions, six vertices per convex piece (relative to the light): its whole shadow
// (the cover: some of the disc is hidden) or its umbra (all of it is). Seen through a vertex w at angle
// a from the light's centre, the disc spans the directions a -+ asin(r / |w|); the extreme ones over the
// piece's vertices are its tangents to the disc: the crossing ones bound the shadow, the outer ones the
// umbra. The piece itself is drawn separately (its triangles); these quads start at its tangent vertices.
in ivec2 in_piece;         // x: the piece's header texel; y: which of the six corners
uniform sampler2D u_pieces;
uniform float u_radius;
uniform bool u_umbra;
uniform vec2 u_scale;
uniform vec2 u_light_clip;

vec4 fetch(int i) { return texelFetch(u_pieces, ivec2(i & 1023, i >> 10), 0); }
vec2 vertex_at(int base, int k) { vec4 t = fetch(base + (k >> 1)); return (k & 1) == 0 ? t.xy : t.zw; }
float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }
vec2 direction(vec2 ref, float angle) { return cos(angle) * ref + sin(angle) * vec2(-ref.y, ref.x); }

void main() {
    vec4 head = fetch(in_piece.x);
    int n = int(mod(head.w, 4096.0)), base = in_piece.x + 1;
    // angles about the piece centre's direction: the piece spans less than half a turn and the disc
    // does not touch it, so a -+ asin(...) never wraps
    vec2 ref = normalize(head.xy);
    float low_shadow = 1e9, low_umbra = 1e9, high_umbra = -1e9, high_shadow = -1e9;
    vec2 wa, wb, wc, wd;
    for (int k = 0; k < n; ++k) {
        vec2 w = vertex_at(base, k);
        float a = atan(cross2(ref, w), dot(ref, w));
        float spread = asin(min(u_radius / length(w), 1.0));
        if (a - spread < low_shadow) { low_shadow = a - spread; wa = w; }
        if (a + spread < low_umbra) { low_umbra = a + spread; wb = w; }
        if (a - spread > high_umbra) { high_umbra = a - spread; wc = w; }
        if (a + spread > high_shadow) { high_shadow = a + spread; wd = w; }
    }
    vec4 corners[6];
    if (!u_umbra) {
        vec4 far_a = vec4(direction(ref, low_shadow), 0.0, 0.0), far_d = vec4(direction(ref, high_shadow), 0.0, 0.0);
        corners = vec4[6](vec4(wa, 0.0, 1.0), far_a, far_d, vec4(wa, 0.0, 1.0), far_d, vec4(wd, 0.0, 1.0));
    } else {
        vec2 db = direction(ref, low_umbra), dc = direction(ref, high_umbra);
        vec4 b = vec4(wb, 0.0, 1.0), c = vec4(wc, 0.0, 1.0);
        if (low_umbra <= high_umbra) {  // diverging: an endless umbra
            corners = vec4[6](b, vec4(db, 0.0, 0.0), vec4(dc, 0.0, 0.0), b, vec4(dc, 0.0, 0.0), c);
        } else {  // converging: a triangle ending where the outer tangents meet (the antumbra beyond)
            float den = cross2(db, dc);
            float s = cross2(wc - wb, dc) / den, t = cross2(wc - wb, db) / den;
            vec4 apex = s >= 0.0 && t >= 0.0 ? vec4(wb + s * db, 0.0, 1.0) : b;  // no crossing ahead: none
            corners = vec4[6](b, apex, c, b, b, b);
        }
    }
    vec4 p = corners[in_piece.y];
    gl_Position = vec4(u_scale * p.xy + u_light_clip * p.w, u_umbra ? -0.5 * p.w : 0.0, p.w);
}
