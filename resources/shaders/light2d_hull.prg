# The hull pass: a solid hull is dark inside (mask 0), an illuminated one lit (mask 1).
VS: light2d_hull_VS.glsl
FS: flat_color_FS.glsl
