"""L0: pure array kernels (numpy only). Batch axes first; planar points are complex numbers."""
