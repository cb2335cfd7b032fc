#version 330 core
// Hull pieces (triangles), relative to the light.
in vec2 in_rel;
uniform vec2 u_scale;
uniform vec2 u_light_clip;
uniform float u_depth;   // the exact method's cover (0) and umbra (-0.5) in the depth buffer

void main() {
    gl_Position = vec4(u_scale * in_rel + u_light_clip, u_depth, 1.0);
}
