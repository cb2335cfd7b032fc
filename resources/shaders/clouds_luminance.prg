# Automatic exposure, step 1: each texel the sum of log2 luminance over its block of the HDR frame, and the count.
VS: fullscreen_VS.glsl
FS: clouds_luminance_FS.glsl
