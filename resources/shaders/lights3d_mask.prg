# A light's shadow-map visibility over the 3D scene (the bench's and tests' mask).
VS: lights3d_scene_VS.glsl
FS: lights3d_mask_FS.glsl
