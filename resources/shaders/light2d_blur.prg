# Separable Gaussian blur of a shadow mask.
VS: fullscreen_VS.glsl
FS: light2d_blur_FS.glsl
