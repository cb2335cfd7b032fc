# Shadow volumes into the stencil, and the scene's depth they are tested against: one vertex shader for both, so
# a caster's own triangle meets the scene's depth bit for bit (depth LESS must fail there). Colour writes are off
# while either draws; the fragment shader is there to link.
VS: shadow_volume_VS.glsl
FS: flat_color_FS.glsl
