#version 330 core
// Exact soft shadows: the visible share of the light's disc at this pixel, occluders fused.
// Seen from the pixel, each convex hull piece in front of the disc hides the disc between two rays; the
// area of the disc between rays at offsets u1 < u2 from its centre (in radii) is g(u2) - g(u1) with
// g(x) = (x sqrt(1 - x^2) + asin x) / pi. The intervals of all pieces are merged before their area is
// taken, so two hulls hiding the same half hide half (Penumbra adds them and hides all).
// Pieces that touch the disc break the interval picture: such lights use light2d_disc_order_FS.glsl
// or light2d_disc_FS.glsl.
//#INCLUDE light2d_pieces.shl
//#INSERT light2d_pieces
uniform bool u_outside;        // the pass runs outside every hull (a solid light's cover leaves them out)
const int MAX_INTERVALS = 16;

float g(float x) {
    x = clamp(x, -1.0, 1.0);
    return (x * sqrt(max(1.0 - x * x, 0.0)) + asin(x)) / PI;
}

// One edge's bound on where the ray p + t d lies inside the piece (t0: entering, t1: leaving).
void clip_edge(vec2 p, vec2 d, vec2 v0, vec2 v1, inout float t0, inout float t1) {
    vec2 normal = vec2(v1.y - v0.y, v0.x - v1.x);
    float den = dot(d, normal), num = dot(v0 - p, normal);
    if (den < 0.0) t0 = max(t0, num / den);
    else if (den > 0.0) t1 = min(t1, num / den);
    else if (num < 0.0) t0 = BIG;
}

// Distance along p + t d at which the ray enters the convex piece (0 when it starts inside), or BIG.
float enter_at(vec2 p, vec2 d, int base, int n) {
    float t0 = 0.0, t1 = BIG;
    int texels = texels_of(n);
    vec2 v0 = fetch(base + texels - 1).zw;
    for (int k = 0; k < texels; ++k) {
        vec4 t = fetch(base + k);
        clip_edge(p, d, v0, t.xy, t0, t1);
        clip_edge(p, d, t.xy, t.zw, t0, t1);
        v0 = t.zw;
    }
    return t0 <= t1 ? t0 : BIG;
}

float visibility(vec2 p) {
    int own;
    float value;
    if (settled_by_own_hull(p, own, value)) return value;
    float dist = length(p);
    float r = u_radius;
    int i = u_begin, base, n;
    vec4 head;
    if (r <= 1e-6 * dist) {  // a point light: one ray towards the centre
        while (next_piece(i, p, 0.0, own, false, head, base, n)) {
            if (enter_at(p, -p / dist, base, n) < dist) return 0.0;
        }
        return 1.0;
    }
    if (dist <= r) return 1.0;  // inside the disc, which no piece touches: all of it is seen
    vec2 axis = -p / dist;
    float lo[MAX_INTERVALS], hi[MAX_INTERVALS];
    int count = 0;
    while (next_piece(i, p, r, own, false, head, base, n)) {
        vec2 w = head.xy - p;
        float wl = length(w);
        // inside a solid hull, or another hull (never, under a solid light's cover: hulls are its umbra)
        if (!u_outside && wl <= head.z && inside(p, base, n)) return 0.0;
        // the piece's extreme vertices as seen from p (pseudo-angles about its centre's direction), then
        // their offsets u = dist sin(angle) from the axis towards the disc, in radii
        vec2 ref = wl > 0.0 ? w / wl : normalize(vertex_at(base, 0) - p);
        float pmin = BIG, pmax = -BIG;
        vec2 vmin, vmax;
        for (int k = 0; k < texels_of(n); ++k) {
            vec4 t = fetch(base + k) - p.xyxy;
            float q1 = pseudo_angle(ref, t.xy), q2 = pseudo_angle(ref, t.zw);
            if (q1 < pmin) { pmin = q1; vmin = t.xy; }
            if (q1 > pmax) { pmax = q1; vmax = t.xy; }
            if (q2 < pmin) { pmin = q2; vmin = t.zw; }
            if (q2 > pmax) { pmax = q2; vmax = t.zw; }
        }
        // going counter-clockwise from vmin to vmax (less than half a turn): an end behind p was
        // reached past the side, so it lies beyond the disc there; both behind: the piece is behind p
        bool front_min = dot(axis, vmin) >= 0.0, front_max = dot(axis, vmax) >= 0.0;
        if (!front_min && !front_max) continue;
        float ul = front_min ? dist * cross2(axis, vmin) / (length(vmin) * r) : -BIG;
        float uh = front_max ? dist * cross2(axis, vmax) / (length(vmax) * r) : BIG;
        ul = max(ul, -1.0);
        uh = min(uh, 1.0);
        if (ul >= uh) continue;
        // behind the disc? (certainly in front when its bounding circle ends before the disc begins)
        if (wl + head.z >= dist - r) {
            float s = 0.5 * (ul + uh) * r / dist;  // sine of the middle ray's angle from the axis
            float c = sqrt(max(1.0 - s * s, 0.0));
            vec2 d = axis * c + vec2(-axis.y, axis.x) * s;
            float t_disc = dist * c - sqrt(max(r * r - (dist * s) * (dist * s), 0.0));
            if (enter_at(p, d, base, n) >= t_disc) continue;
        }
        if (ul <= -1.0 && uh >= 1.0) return 0.0;  // this piece alone hides the whole disc
        if (count < MAX_INTERVALS) {
            lo[count] = ul; hi[count] = uh; ++count;
        } else {  // more separate occluders than slots: widen the last (conservative)
            lo[count - 1] = min(lo[count - 1], ul); hi[count - 1] = max(hi[count - 1], uh);
        }
    }
    for (int a = 1; a < count; ++a) {  // insertion sort by lower end
        float kl = lo[a], kh = hi[a];
        int b = a - 1;
        while (b >= 0 && lo[b] > kl) { lo[b + 1] = lo[b]; hi[b + 1] = hi[b]; --b; }
        lo[b + 1] = kl; hi[b + 1] = kh;
    }
    float hidden = 0.0, reach = -1.0;
    for (int a = 0; a < count; ++a) {
        float start = max(lo[a], reach);
        if (hi[a] > start) hidden += g(hi[a]) - g(start);
        reach = max(reach, hi[a]);
    }
    return clamp(1.0 - hidden, 0.0, 1.0);
}

void main() {
    frag_color = vec4(0.0, 0.0, 0.0, visibility(v_rel));
}
