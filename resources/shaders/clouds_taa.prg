# Temporal anti-aliasing of the cloud buffer: the reprojected history, clamped, blended with this frame.
VS: fullscreen_VS.glsl
FS: clouds_taa_FS.glsl
