#version 330 core
// Exact soft shadows where hull pieces enter the light's disc and no two hulls overlap: the visible
// share of the disc at this pixel, the pieces taken nearest first (light2d_disc_order.shl).
//#INCLUDE light2d_pieces.shl
//#INSERT light2d_pieces
//#INCLUDE light2d_disc_order.shl
//#INSERT light2d_disc_order

void main() {
    int own;
    float value;
    if (!settled_by_own_hull(v_rel, own, value)) value = ordered_share(v_rel, own);
    frag_color = vec4(0.0, 0.0, 0.0, value);
}
