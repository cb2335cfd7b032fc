#version 330 core
// Hull pieces (triangles), relative to the light.
in vec2 in_rel;
uniform vec2 u_scale;
uniform vec2 u_light_clip;

void main() {
    gl_Position = vec4(u_scale * in_rel + u_light_clip, 0.0, 1.0);
}
