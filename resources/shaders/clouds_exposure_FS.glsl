#version 330 core

uniform sampler2D u_sums;   // the luminance pass's blocks, mipmapped: the last level their mean
uniform int u_top;          // that level
uniform sampler2D u_average;  // the last frame's output
uniform float u_adapt;      // the share of the way to the frame's average this frame moves; 1 at a restart

out vec2 out_average;       // (adapted, this frame's) mean log2 luminance

void main() {
    vec2 sums = texelFetch(u_sums, ivec2(0), u_top).rg;
    float frame = sums.x / sums.y;
    float adapted = u_adapt >= 1.0 ? frame : mix(texelFetch(u_average, ivec2(0), 0).r, frame, u_adapt);
    out_average = vec2(adapted, frame);
}
