# One-pass ray tracer (seed 003, F4-F11): the ray-box slab test in the fragment shader.
VS: fullscreen_VS.glsl
FS: raytrace_FS.glsl
