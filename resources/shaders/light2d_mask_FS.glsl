#version 330 core
// A mask texture into the lightmap's alpha: jittered samples add the mean of their four channels,
// blurred hard shadows copy one channel.
uniform sampler2D u_mask;
uniform vec4 u_weights;
out vec4 frag_color;

void main() {
    frag_color = vec4(dot(texelFetch(u_mask, ivec2(gl_FragCoord.xy), 0), u_weights));
}
