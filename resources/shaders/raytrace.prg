# One-pass ray tracer (seed 003, F4-F11; and a scalar volume's modes, r_scalarMode): the ray-box slab test in the
# fragment shader. Drawn with SCALAR_MODE defined: 0 for the F-modes, a scalar mode's index for it (scalar_modes.shl).
VS: fullscreen_VS.glsl
FS: raytrace_FS.glsl
