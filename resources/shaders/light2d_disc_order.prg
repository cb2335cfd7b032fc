# Exact soft-shadow mask of a light whose disc hull pieces enter, where no two hulls overlap.
VS: light2d_quad_VS.glsl
FS: light2d_disc_order_FS.glsl
