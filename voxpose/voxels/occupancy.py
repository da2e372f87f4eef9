"""The voxels a body model fills: every voxel whose centre lies inside one of its solids, for many frames at once.

A voxel ``ijk`` of side ``l_res`` has its centre at ``(ijk + 0.5) * l_res`` (``voxpose.voxels.sequence``), and a
solid is ``{x : (x - c)^T Sigma^-1 (x - c) <= 1}`` with ``Sigma^-1 = R diag(r^-2) R^T``
(``voxpose.voxels.body.Ellipsoids``): a centre is inside when its coordinates along the solid's axes, divided by
the semi-axes, have a norm of at most 1. Along a row of voxels in z, the centres inside form one run between
the two roots of that quadratic in z, so only the rows (i, j) of each solid's axis-aligned bounding box
(half-extents ``sqrt(diag(Sigma))``) are visited, not every voxel. All (frame, solid) rows are enumerated
together as one flat array (from one running index), so there is no loop over frames or solids. This is the
body as the carving would see it with perfect silhouettes from every direction, without the cameras:
``voxpose.apply.root_fit`` uses it to place the estimated body on a carved hull.
"""

import numpy as np

from voxpose.voxels.body import Ellipsoids


def occupied_voxels(ellipsoids: Ellipsoids, l_res: float) -> tuple[np.ndarray, np.ndarray]:
    """Voxels of side ``l_res`` inside the solids of every frame (module docstring).

    Returns
    -------
    frame : (N,) int64 frame index of each voxel (0 for solids of a single frame), sorted.
    ijk : (N, 3) int64 voxel indices; each (frame, voxel) appears once.
    """
    centres = ellipsoids.centres.reshape(-1, ellipsoids.centres.shape[-2], 3)
    n_frames, n_solids = centres.shape[:2]
    rotations = ellipsoids.rotations.reshape(-1, 3, 3)
    radii = np.broadcast_to(ellipsoids.radii, (n_frames, n_solids, 3)).reshape(-1, 3)
    centres = centres.reshape(-1, 3)
    scaled = rotations / radii[:, None, :]
    inverse = scaled @ np.swapaxes(scaled, -1, -2)  # Sigma^-1
    half = np.sqrt(np.einsum("nij,nj->ni", rotations**2, radii**2))  # sqrt(diag(Sigma))
    lo = np.ceil((centres[:, :2] - half[:, :2]) / l_res - 0.5).astype(np.int64)
    size = np.maximum(np.floor((centres[:, :2] + half[:, :2]) / l_res - 0.5).astype(np.int64) - lo + 1, 0)
    # one row of voxels along z per (solid, i, j) of the box: its centres inside form one run, from the roots
    # of the quadratic (x, y, z)^T Sigma^-1 (x, y, z) = 1 in z
    counts = size.prod(axis=1)
    solid = np.repeat(np.arange(len(counts)), counts)
    local = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    i = lo[solid, 0] + local // size[solid, 1]
    j = lo[solid, 1] + local % size[solid, 1]
    x, y = (i + 0.5) * l_res - centres[solid, 0], (j + 0.5) * l_res - centres[solid, 1]
    q = inverse[solid]
    a = q[:, 2, 2]
    b = q[:, 0, 2] * x + q[:, 1, 2] * y
    c = q[:, 0, 0] * x * x + 2.0 * q[:, 0, 1] * x * y + q[:, 1, 1] * y * y - 1.0
    disc = b * b - a * c
    hit = disc >= 0.0
    solid, i, j, a, b, root = solid[hit], i[hit], j[hit], a[hit], b[hit], np.sqrt(disc[hit])
    k0 = np.ceil((centres[solid, 2] + (-b - root) / a) / l_res - 0.5).astype(np.int64)
    k1 = np.floor((centres[solid, 2] + (-b + root) / a) / l_res - 0.5).astype(np.int64)
    run = np.maximum(k1 - k0 + 1, 0)
    step = np.arange(run.sum()) - np.repeat(np.cumsum(run) - run, run)
    frame = np.repeat(solid // n_solids, run)
    ijk = np.stack([np.repeat(i, run), np.repeat(j, run), np.repeat(k0, run) + step], axis=1)
    if not len(ijk):
        return frame, ijk
    # each voxel once: mark a box per frame (cheaper than sorting), read the marks back in order
    starts = np.searchsorted(frame, np.arange(n_frames))
    present = np.flatnonzero(np.diff(np.r_[starts, len(ijk)]) > 0)
    lo = np.zeros((n_frames, 3), dtype=np.int64)
    lo[present] = np.minimum.reduceat(ijk, starts[present], axis=0)
    rel = ijk - lo[frame]
    span = rel.max(axis=0) + 1
    marks = np.zeros(n_frames * int(span.prod()), dtype=bool)
    marks[((frame * span[0] + rel[:, 0]) * span[1] + rel[:, 1]) * span[2] + rel[:, 2]] = True
    index = np.unravel_index(np.flatnonzero(marks), (n_frames, *span))
    frame = index[0]
    return frame, np.stack(index[1:], axis=1) + lo[frame]
