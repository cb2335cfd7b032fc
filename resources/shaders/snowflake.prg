# Koch snowflake (seed 003, G80test): one input point per chunk of the outline.
VS: snowflake_VS.glsl
GS: snowflake_GS.glsl
FS: flat_color_FS.glsl
