# The three tables of the physical sky copied into one atlas texture (one texture unit for the clouds' passes).
VS: fullscreen_VS.glsl
FS: atmosphere_pack_FS.glsl
