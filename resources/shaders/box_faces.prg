# Two-pass ray setup, pass 1 (F1-F3): the box's front faces write where each ray enters it.
VS: box_VS.glsl
FS: box_entry_FS.glsl
