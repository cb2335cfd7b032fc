# The 3D lights' offscreen frame into the host's framebuffer (any sample count), clamped to 0..1.
VS: fullscreen_VS.glsl
FS: lights3d_present_FS.glsl
