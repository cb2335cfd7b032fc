# Jittered hard-shadow samples or a blurred hard shadow, moved into the lightmap's alpha.
VS: fullscreen_VS.glsl
FS: light2d_mask_FS.glsl
