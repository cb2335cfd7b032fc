# The physical sky as seen from the camera's altitude with the sun at its elevation (Hillaire 2020's sky-view table).
VS: fullscreen_VS.glsl
FS: atmosphere_sky_view_FS.glsl
