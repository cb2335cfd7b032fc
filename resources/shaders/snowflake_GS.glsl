#version 330 core
#GS_input: POINTS
#GS_output: LINE_STRIP
#GS_count: 65
// GLSL has no recursion, and one emission must stay within 256 vertices (the portable minimum),
// so each input point draws one chunk: a subtree of at most 4^3 = 64 segments (65 vertices).
// A segment is addressed by its base-4 path from its triangle edge, so a chunk walks down
// to its subtree root and then to each leaf: no stack needed at all.

//#INCLUDE koch.shl
//#INSERT koch_child

uniform int u_levels;       // m = ceil(level): subdivisions in all
uniform int u_chunk_depth;  // subdivisions inside one chunk: min(m, 3)
uniform float u_last_t;     // peak height of the m-th subdivision (fractional levels)
uniform vec2 u_scale;       // world -> clip
uniform vec2 u_offset;

in vec3 vs_flake[];
flat in int vs_chunk[];

out vec2 v_world;

void emit(vec2 p) {
    v_world = p;
    gl_Position = vec4(p * u_scale + u_offset, 0.0, 1.0);
    EmitVertex();
}

void main() {
    int prefix = u_levels - u_chunk_depth;
    int per_edge = 1 << (2 * prefix);
    int edge = vs_chunk[0] / per_edge;
    int path = vs_chunk[0] - edge * per_edge;
    vec2 a = koch_corner(vs_flake[0], edge);
    vec2 b = koch_corner(vs_flake[0], edge + 1);
    for (int i = prefix - 1; i >= 0; --i)
        koch_child(a, b, (path >> (2 * i)) & 3, 1.0);

    int leaves = 1 << (2 * u_chunk_depth);
    vec2 e = b;
    for (int j = 0; j < leaves; ++j) {
        vec2 s = a;
        e = b;
        for (int i = u_chunk_depth - 1; i >= 0; --i)
            koch_child(s, e, (j >> (2 * i)) & 3, i == 0 ? u_last_t : 1.0);
        emit(s);
    }
    emit(e);
    EndPrimitive();
}
