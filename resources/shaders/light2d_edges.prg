# Shadow quads of hull edges: Penumbra's soft wedges, or hard shadows from one emitting point.
VS: light2d_edges_VS.glsl
FS: light2d_edges_FS.glsl
