# A 2D light's quad, added into the lightmap weighted by its shadow mask (destination alpha).
VS: light2d_quad_VS.glsl
FS: light2d_light_FS.glsl
