# Editor marks in pixels over a frame (the 3D lights' markers and gizmo), each vertex its own colour.
VS: overlay2d_VS.glsl
FS: vertex_colour_FS.glsl
