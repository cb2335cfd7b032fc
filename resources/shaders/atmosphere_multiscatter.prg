# The physical sky's multiple-scattering table Psi_ms(r, mu_s) (Hillaire 2020), from the transmittance table.
VS: fullscreen_VS.glsl
FS: atmosphere_multiscatter_FS.glsl
