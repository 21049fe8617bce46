"""Asset library: catalog, procedural meshes, the six-step workflow, cache and MJCF."""
