# One-pass ray tracer (seed 003, F4-F11; and a scalar volume's modes, r_scalarMode): the ray-box slab test in the
# fragment shader.
VS: fullscreen_VS.glsl
FS: raytrace_FS.glsl
