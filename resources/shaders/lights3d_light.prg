# One light of the 3D scene: seed 004's per-pixel point, spot and directional lighting, its shadow map if any.
VS: lights3d_scene_VS.glsl
FS: lights3d_light_FS.glsl
