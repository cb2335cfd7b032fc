# The 3D scene's depth pre-pass, coloured by the ambient light; the lights add to it (depth EQUAL).
VS: lights3d_scene_VS.glsl
FS: lights3d_ambient_FS.glsl
