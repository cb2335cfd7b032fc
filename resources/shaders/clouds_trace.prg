# The cloud march into the cloud buffer (every pixel, or one of each 4x4 block when reprojecting).
VS: fullscreen_VS.glsl
FS: clouds_trace_FS.glsl
