# Two-pass ray setup, pass 2 (F1-F3): the back faces give the exit, pass 1's buffer the entry
# (or the eye, when it is inside the box and no front face was drawn).
VS: box_VS.glsl
FS: raytrace2_FS.glsl
