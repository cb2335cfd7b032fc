# Exact soft-shadow mask of a light whose disc hull pieces enter, written into the lightmap's alpha.
VS: light2d_quad_VS.glsl
FS: light2d_disc_FS.glsl
