# A reduced-resolution frame stretched over the screen (interactive rendering).
VS: fullscreen_VS.glsl
FS: upscale_FS.glsl
