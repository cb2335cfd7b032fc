# Exact soft-shadow mask of one light, written into the lightmap's alpha.
VS: light2d_quad_VS.glsl
FS: light2d_exact_FS.glsl
