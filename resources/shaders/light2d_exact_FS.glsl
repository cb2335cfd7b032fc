#version 330 core
// Exact soft shadows: the visible share of the light's disc at this pixel, occluders fused.
// Seen from the pixel, each convex hull piece in front of the disc hides the disc between two rays; the
// area of the disc between rays at offsets u1 < u2 from its centre (in radii) is g(u2) - g(u1) with
// g(x) = (x sqrt(1 - x^2) + asin x) / pi. The intervals of all pieces are merged before their area is
// taken, so two hulls hiding the same half hide half (Penumbra adds them and hides all).
// Pieces that touch the disc break the interval picture; there the disc is sampled (u_touching).
in vec2 v_uv;
in vec2 v_rel;                 // this pixel, relative to the light's centre
uniform sampler2D u_pieces;    // per piece: (n, hull, 0, 0), (centre x, y, bounding radius, 0), n/2 texels of vertices
uniform int u_begin;
uniform int u_end;
uniform float u_radius;
uniform int u_shadow_type;     // 0 solid, 1 illuminated, 2 occluded
uniform bool u_touching;
uniform int u_disc_samples;
out vec4 frag_color;

const int MAX_INTERVALS = 16;
const float PI = 3.14159265358979;
const float BIG = 1e30;

vec4 fetch(int i) { return texelFetch(u_pieces, ivec2(i & 1023, i >> 10), 0); }
vec2 vertex_at(int base, int k) { vec4 t = fetch(base + (k >> 1)); return (k & 1) == 0 ? t.xy : t.zw; }

float g(float x) {
    x = clamp(x, -1.0, 1.0);
    return (x * sqrt(max(1.0 - x * x, 0.0)) + asin(x)) / PI;
}

bool inside(vec2 p, int base, int n) {
    vec2 v0 = vertex_at(base, n - 1);
    for (int k = 0; k < n; ++k) {
        vec2 v1 = vertex_at(base, k);
        vec2 e = v1 - v0;
        if (e.x * (p.y - v0.y) - e.y * (p.x - v0.x) < 0.0) return false;
        v0 = v1;
    }
    return true;
}

// Distance along p + t d at which the ray enters the convex piece (0 when it starts inside), or BIG.
float enter_at(vec2 p, vec2 d, int base, int n) {
    float t0 = 0.0, t1 = BIG;
    vec2 v0 = vertex_at(base, n - 1);
    for (int k = 0; k < n; ++k) {
        vec2 v1 = vertex_at(base, k);
        vec2 normal = vec2(v1.y - v0.y, v0.x - v1.x);
        float den = dot(d, normal), num = dot(v0 - p, normal);
        if (den < 0.0) t0 = max(t0, num / den);
        else if (den > 0.0) t1 = min(t1, num / den);
        else if (num < 0.0) return BIG;
        v0 = v1;
    }
    return t0 <= t1 ? t0 : BIG;
}

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// The hull containing p (-1 if none); solid and illuminated hulls settle the pixel at once.
int containing_hull(vec2 p, out bool settled, out float value) {
    settled = false;
    for (int i = u_begin; i < u_end;) {
        vec4 head = fetch(i), bound = fetch(i + 1);
        int n = int(head.x);
        if (distance(p, bound.xy) <= bound.z && inside(p, i + 2, n)) {
            if (u_shadow_type != 2) { settled = true; value = u_shadow_type == 0 ? 0.0 : 1.0; }
            return int(head.y);
        }
        i += 2 + (n + 1) / 2;
    }
    return -1;
}

float sampled(vec2 p, int own) {
    // Vogel disc: area-uniform, stratified in radius, golden-angle in angle
    int hidden = 0;
    for (int s = 0; s < u_disc_samples; ++s) {
        float rr = u_radius * sqrt((float(s) + 0.5) / float(u_disc_samples));
        float a = float(s) * 2.39996323;
        vec2 q = rr * vec2(cos(a), sin(a));
        vec2 d = q - p;
        for (int i = u_begin; i < u_end;) {
            vec4 head = fetch(i);
            int n = int(head.x);
            if (int(head.y) != own && enter_at(p, d, i + 2, n) < 1.0) { ++hidden; break; }
            i += 2 + (n + 1) / 2;
        }
    }
    return 1.0 - float(hidden) / float(u_disc_samples);
}

float visibility(vec2 p) {
    bool settled;
    float value;
    int own = containing_hull(p, settled, value);
    if (settled) return value;
    own = u_shadow_type == 2 ? own : -1;
    float dist = length(p);
    if (u_touching) return sampled(p, own);
    float r = u_radius;
    if (r <= 1e-6 * dist) {  // a point light: one ray towards the centre
        for (int i = u_begin; i < u_end;) {
            vec4 head = fetch(i);
            int n = int(head.x);
            if (int(head.y) != own && enter_at(p, -p / dist, i + 2, n) < dist) return 0.0;
            i += 2 + (n + 1) / 2;
        }
        return 1.0;
    }
    if (dist <= r) return 1.0;  // inside the disc, which no piece touches: all of it is seen
    vec2 axis = -p / dist;
    float beta = asin(r / dist);
    float lo[MAX_INTERVALS], hi[MAX_INTERVALS];
    int count = 0;
    for (int i = u_begin; i < u_end;) {
        vec4 head = fetch(i), bound = fetch(i + 1);
        int n = int(head.x), base = i + 2;
        i += 2 + (n + 1) / 2;
        if (int(head.y) == own) continue;
        vec2 w = bound.xy - p;
        float wl = length(w);
        if (wl > bound.z) {
            // the piece's bounding circle misses the cone of rays towards the disc, or lies beyond it
            if (acos(clamp(dot(w, axis) / wl, -1.0, 1.0)) - asin(bound.z / wl) > beta) continue;
            if (wl - bound.z > dist + r) continue;
        } else if (inside(p, base, n)) {
            return 0.0;  // inside another hull
        }
        vec2 ref = wl > 0.0 ? w / wl : normalize(vertex_at(base, 0) - p);
        float centre = atan(cross2(axis, ref), dot(axis, ref));
        float amin = BIG, amax = -BIG;
        for (int k = 0; k < n; ++k) {
            vec2 v = vertex_at(base, k) - p;
            float a = atan(cross2(ref, v), dot(ref, v));
            amin = min(amin, a);
            amax = max(amax, a);
        }
        float l = centre + amin, h = centre + amax;
        if (l > beta) { l -= 2.0 * PI; h -= 2.0 * PI; }
        else if (h < -beta) { l += 2.0 * PI; h += 2.0 * PI; }
        l = max(l, -beta);
        h = min(h, beta);
        if (l >= h) continue;
        float m = 0.5 * (l + h);
        vec2 d = vec2(axis.x * cos(m) - axis.y * sin(m), axis.x * sin(m) + axis.y * cos(m));
        float s = dist * sin(m);
        float t_disc = dist * cos(m) - sqrt(max(r * r - s * s, 0.0));
        if (enter_at(p, d, base, n) >= t_disc) continue;  // the piece lies behind the disc
        float ul = dist * sin(l) / r, uh = dist * sin(h) / r;
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
