#version 330 core
// Linear depth: the distance to the light from the map's near distance to its far one, or the orthographic view's
// own depth.
uniform vec3 u_light;
uniform float u_near;
uniform float u_far;  // 0: orthographic
in vec3 v_world;

void main() {
    gl_FragDepth = u_far > 0.0 ? clamp((length(v_world - u_light) - u_near) / (u_far - u_near), 0.0, 1.0)
                               : gl_FragCoord.z;
}
