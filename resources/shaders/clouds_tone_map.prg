# The HDR frame to the output: exposure, the tone curve, sRGB encoding.
VS: fullscreen_VS.glsl
FS: clouds_tone_map_FS.glsl
