# A light's shadow map: the casters' depths as seen from the light, linear (app/gl/lights3d/shadow_map.py).
VS: shadow_map_VS.glsl
FS: shadow_map_FS.glsl
