# Temporal reprojection: this frame's traced pixels, the rest from the last frame (traced where it has none).
VS: fullscreen_VS.glsl
FS: clouds_resolve_FS.glsl
