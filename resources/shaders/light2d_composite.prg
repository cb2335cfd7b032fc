# The diffuse map multiplied by the lightmap, over the whole screen.
VS: fullscreen_VS.glsl
FS: light2d_composite_FS.glsl
