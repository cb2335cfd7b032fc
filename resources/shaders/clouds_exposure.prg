# Automatic exposure, step 2: the frame's log-average luminance, and the adapted one that the exposure follows.
VS: fullscreen_VS.glsl
FS: clouds_exposure_FS.glsl
