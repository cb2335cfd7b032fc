#version 330 core
// Seed 000's last step: the scene (the diffuse map, tiled in world space) times the lightmap.
in vec2 v_ndc;
uniform sampler2D u_diffuse;
uniform sampler2D u_lightmap;
uniform vec2 u_world_scale;   // ndc -> world: world = ndc * scale + offset
uniform vec2 u_world_offset;
uniform bool u_lightmap_only;
out vec4 frag_color;

void main() {
    vec3 light = texture(u_lightmap, v_ndc * 0.5 + 0.5).rgb;
    vec2 world = v_ndc * u_world_scale + u_world_offset;
    vec3 diffuse = u_lightmap_only ? vec3(1.0) : texture(u_diffuse, world / vec2(textureSize(u_diffuse, 0))).rgb;
    frag_color = vec4(diffuse * light, 1.0);
}
