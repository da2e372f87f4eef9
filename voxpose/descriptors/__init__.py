"""Shape descriptors (Section 4): 3D shape contexts at the basis voxels (Eq. 4, world-aligned, soft votes).

``shape_context`` is the direct definition (the reference), ``lut`` the lookup-table fast path the pipeline
uses, ``file`` the per-motion descriptor file; ``contour`` the 2D shape contexts of silhouette contours for
the Agarwal & Triggs-style comparison.
"""
