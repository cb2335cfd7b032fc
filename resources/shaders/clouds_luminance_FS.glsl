#version 330 core
//#INCLUDE tone_map.shl
//#INSERT tone_map

uniform sampler2D u_hdr;        // the frame's linear radiance
uniform ivec2 u_cells;          // this target's size: the frame cut into as many blocks
uniform float u_min_luminance;  // no log of 0

out vec2 out_sum;  // (sum of log2 luminance, pixels): the mipmaps' last level is their mean, whose ratio is exact

void main() {
    ivec2 size = textureSize(u_hdr, 0);
    ivec2 cell = ivec2(gl_FragCoord.xy);
    ivec2 lo = cell * size / u_cells, hi = (cell + 1) * size / u_cells;
    float sum = 0.0;
    for (int y = lo.y; y < hi.y; y++) {
        for (int x = lo.x; x < hi.x; x++) {
            sum += log2(max(dot(texelFetch(u_hdr, ivec2(x, y), 0).rgb, LUMINANCE), u_min_luminance));
        }
    }
    out_sum = vec2(sum, float((hi.x - lo.x) * (hi.y - lo.y)));
}
