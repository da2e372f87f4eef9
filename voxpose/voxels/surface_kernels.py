"""Compiled (numba) kernels of the basis voxels' grid down-sampling (:func:`voxpose.voxels.surface.basis_indices`),
selected by :mod:`voxpose.kernels`.

The numpy path counts the non-empty cells of each trial cell size and then picks a voxel per cell with about a
dozen array operations on a couple of thousand voxels each, so per-call overhead is most of its 0.6 ms per frame.
These loops compute the same cells (``floor((x + offset) / cell)`` of the same numbers), the same centroids (sums
in voxel order, as ``np.bincount``) and the same squared distances (summed over the axes in order), and break ties
towards the lower index as the numpy path's stable sort does, so they pick the same voxels
(``tests/voxels/test_surface.py``).
"""

import numpy as np

from voxpose.kernels import jit


@jit
def _cells(ijk, cell, offset):  # pragma: no cover (compiled)
    """``(key (N,), n_keys)``: each voxel's cell as a flat index into the cells' bounding box."""
    n = ijk.shape[0]
    c = np.empty((n, 3), dtype=np.int64)
    for v in range(n):
        for a in range(3):
            c[v, a] = np.int64(np.floor((ijk[v, a] + offset[a]) / cell))
    lo = c[0].copy()
    hi = c[0].copy()
    for v in range(n):
        for a in range(3):
            lo[a] = min(lo[a], c[v, a])
            hi[a] = max(hi[a], c[v, a])
    size = hi - lo + 1
    key = np.empty(n, dtype=np.int64)
    for v in range(n):
        key[v] = ((c[v, 0] - lo[0]) * size[1] + c[v, 1] - lo[1]) * size[2] + c[v, 2] - lo[2]
    return key, size[0] * size[1] * size[2]


@jit
def count_cells(ijk, cell, offset):  # pragma: no cover (compiled)
    """Number of non-empty cells of side ``cell`` on the grid shifted by ``offset`` (3,)."""
    key, n_keys = _cells(ijk, cell, offset)
    seen = np.zeros(n_keys, dtype=np.bool_)
    count = 0
    for v in range(key.shape[0]):
        if not seen[key[v]]:
            seen[key[v]] = True
            count += 1
    return count


@jit
def grid_sample(ijk, cell, offset):  # pragma: no cover (compiled)
    """Indices (sorted) of the voxel nearest its cell's centroid in every non-empty cell (ties: lower index)."""
    n = ijk.shape[0]
    key, n_keys = _cells(ijk, cell, offset)
    counts = np.zeros(n_keys, dtype=np.int64)
    sums = np.zeros((n_keys, 3))
    for v in range(n):
        counts[key[v]] += 1
        for a in range(3):
            sums[key[v], a] += ijk[v, a]
    best = np.full(n_keys, np.inf)
    winner = np.full(n_keys, -1, dtype=np.int64)
    for v in range(n):
        k = key[v]
        dist = 0.0
        for a in range(3):
            d = ijk[v, a] - sums[k, a] / counts[k]
            dist += d * d
        if dist < best[k]:
            best[k] = dist
            winner[k] = v
    chosen = np.zeros(n, dtype=np.bool_)
    for k in range(n_keys):
        if winner[k] >= 0:
            chosen[winner[k]] = True
    return np.flatnonzero(chosen)
