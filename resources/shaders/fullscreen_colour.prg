# One colour over the whole target (what the stencil test lets through: the 3D lights' stencil debug view).
VS: fullscreen_VS.glsl
FS: flat_color_FS.glsl
