# The volume's 3D view until the ray tracer's modes arrive: one pass, ray-box slab test,
# front-to-back compositing of the RGBA voxels.
VS: fullscreen_VS.glsl
FS: volume_FS.glsl
