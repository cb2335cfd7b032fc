#version 330 core
// Exact soft shadows where hull pieces enter the light's disc: the visible share of the disc at this
// pixel, the disc clipped by the union of the pieces' shadows (light2d_disc.shl). A program of its own:
// compiled into light2d_exact_FS.glsl, its code slowed the interval method down twofold on llvmpipe.
//#INCLUDE light2d_pieces.shl
//#INSERT light2d_pieces
//#INCLUDE light2d_disc.shl
//#INSERT light2d_disc

void main() {
    int own;
    float value;
    if (!settled_by_own_hull(v_rel, own, value)) value = clipped_share(v_rel, own);
    frag_color = vec4(0.0, 0.0, 0.0, value);
}
