# The volume box's edges (key f, wireframe).
VS: box_VS.glsl
FS: flat_color_FS.glsl
