"""From a posed body (or real silhouettes) to voxels (Sections 4 and 6).

The articulated body of ellipsoids and spheres (``body``, Section 6) is rendered into calibrated cameras on a
circle (``cameras``, ``render``), carved into a visual hull at ``l_res = h_sub / 60`` (``carve``, Section 4),
and reduced to surface and basis voxels (``surface``, Figure 2); ``voxelize`` runs the whole stage and
``sequence`` holds its result and file layout. ``degrade`` damages silhouettes as real segmentation does,
``silhouettes`` reads and writes folders of silhouette masks.
"""
