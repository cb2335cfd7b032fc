# A scalar volume's modes (r_scalarMode but colour), one program each (SCALAR_MODE defined: the mode's number):
# the one-pass ray tracer without the F-modes' code and the other modes', which llvmpipe pays for on every pixel.
VS: fullscreen_VS.glsl
FS: raytrace_scalar_FS.glsl
