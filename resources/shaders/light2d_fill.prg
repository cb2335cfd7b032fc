# One value over the scissored region, in the channels the colour mask lets through.
VS: fullscreen_VS.glsl
FS: flat_color_FS.glsl
