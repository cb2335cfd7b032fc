#version 330 core
// Linear depth: the distance to the light over the map's far distance, or the orthographic view's own depth.
uniform vec3 u_light;
uniform float u_far;  // 0: orthographic
in vec3 v_world;

void main() {
    gl_FragDepth = u_far > 0.0 ? length(v_world - u_light) / u_far : gl_FragCoord.z;
}
