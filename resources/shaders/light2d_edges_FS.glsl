#version 330 core
// Penumbra: occlusion(p) = r (3 - r^2) / 4 + 0.5, r = clamp(p.x / p.y, -1, 1); alpha = oA + oB - 1,
// subtracted from the mask. Hard: the mask becomes 0 where the quad lies.
// Fix: beside an end point but nearer the light than it (p.y <= 0, inside the quad only on the edge's
// side) the seed's ratio flips sign and lights the umbra; there the side alone decides.
in vec2 v_penumbra_a;
in vec2 v_penumbra_b;
in float v_clip;
in float v_soft;
out vec4 frag_color;

float occlusion(vec2 p) {
    float r = p.y > 0.0 ? clamp(p.x / p.y, -1.0, 1.0) : sign(p.x);
    return r * (3.0 - r * r) * 0.25 + 0.5;
}

void main() {
    if (v_soft > 0.5) {
        if (v_clip < 0.0) discard;  // the edge faces the light
        frag_color = vec4(occlusion(v_penumbra_a) + occlusion(v_penumbra_b) - 1.0);
    } else {
        frag_color = vec4(0.0);
    }
}
