#version 330 core
//#INCLUDE tone_map.shl
//#INSERT tone_map

uniform sampler2D u_hdr;       // the frame's linear radiance, the output's size
uniform sampler2D u_average;   // (adapted, this frame's) mean log2 luminance
uniform int u_auto;            // 1: automatic exposure, u_ev its compensation
uniform float u_ev;
uniform float u_key;           // log2 of the luminance the adapted average is shown at
uniform float u_auto_range;    // the automatic exposure's limit either way, EV
uniform int u_curve;

out vec4 frag_color;

void main() {
    float ev = u_ev;
    if (u_auto == 1) ev += clamp(u_key - texelFetch(u_average, ivec2(0), 0).r, -u_auto_range, u_auto_range);
    frag_color = vec4(tone_map(texelFetch(u_hdr, ivec2(gl_FragCoord.xy), 0).rgb, exp2(ev), u_curve), 1.0);
}
