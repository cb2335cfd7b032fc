# Plain 2D line segments in world space (CPU-built geometry, overlays).
VS: lines2d_VS.glsl
FS: flat_color_FS.glsl
