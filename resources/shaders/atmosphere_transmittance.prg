# The physical sky's transmittance table: from each (r, mu) to the top of the atmosphere (Hillaire 2020).
VS: fullscreen_VS.glsl
FS: atmosphere_transmittance_FS.glsl
