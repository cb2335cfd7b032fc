# The exact method's cover (every piece's shadow) and umbras, written into the depth buffer.
VS: light2d_region_VS.glsl
FS: flat_color_FS.glsl
