# The clouds over the cirrus, the sky and the ground, at the output's size, as linear radiance (or the sample-count view).
VS: fullscreen_VS.glsl
FS: clouds_composite_FS.glsl
