"""Compiled (numba) kernel of the body frame's resampling (:func:`voxpose.descriptors.body_frame.body_voxels`),
selected by :mod:`voxpose.kernels`.

The numpy path turns the hull, builds the source grid, gathers every column of the turned grid and finds the
surface again in about thirty array operations on a few thousand voxels, so most of its 1.2 ms per frame is
per-call overhead and temporaries. This loop does the same arithmetic in the same order (the turn's products and
sums, ``rint`` of the same numbers; no fused multiply-adds, as numba does not contract them without fastmath),
so it gives the numpy path's voxels, surface and order exactly (``tests/descriptors/test_body_frame.py``).
"""

import numpy as np

from voxpose.kernels import jit


@jit
def turned_voxels(ijk, to_body, to_world, px, pz):  # pragma: no cover (compiled)
    """``(body (N', 3) int64, surface (N',) bool)``: the occupied cells of the grid turned about the vertical
    through ``(px, pz)``, in the order x, then y, then z, and which have an empty 6-neighbour.

    ``to_body`` and ``to_world`` are ``(cos, sin)`` of ``-h0`` and ``h0`` as ``body_frame._yaw`` computes them.
    """
    n = ijk.shape[0]
    c0, s0 = to_body[0], to_body[1]
    c1, s1 = to_world[0], to_world[1]
    lo = ijk[0].copy()
    hi = ijk[0].copy()
    t_lo = np.full(3, np.inf)
    t_hi = np.full(3, -np.inf)
    for v in range(n):
        x = ijk[v, 0] - px
        y = ijk[v, 1] - 0.0
        z = ijk[v, 2] - pz
        turned = (c0 * x + s0 * z, y, -s0 * x + c0 * z)
        for a in range(3):
            lo[a] = min(lo[a], ijk[v, a])
            hi[a] = max(hi[a], ijk[v, a])
            t_lo[a] = min(t_lo[a], turned[a])
            t_hi[a] = max(t_hi[a], turned[a])
    size = hi - lo + 1
    grid = np.zeros((size[0], size[2], size[1]), dtype=np.bool_)  # (x, z, y): a column is contiguous
    for v in range(n):
        grid[ijk[v, 0] - lo[0], ijk[v, 2] - lo[2], ijk[v, 1] - lo[1]] = True
    first = np.empty(3, dtype=np.int64)
    shape = np.empty(3, dtype=np.int64)
    for a in range(3):
        first[a] = np.int64(np.floor(t_lo[a])) - 1
        shape[a] = np.int64(np.ceil(t_hi[a])) + 1 - first[a] + 1
    occupied = np.zeros((shape[0], shape[1], shape[2]), dtype=np.bool_)
    count = 0
    for i in range(shape[0]):
        x = first[0] + i
        for k in range(shape[2]):
            z = first[2] + k
            sx = np.int64(np.rint(c1 * x + s1 * z + px)) - lo[0]
            sz = np.int64(np.rint(-s1 * x + c1 * z + pz)) - lo[2]
            if sx < 0 or sx >= size[0] or sz < 0 or sz >= size[2]:
                continue
            for j in range(shape[1]):
                sy = first[1] + j - lo[1]
                if 0 <= sy < size[1] and grid[sx, sz, sy]:
                    occupied[i, j, k] = True
                    count += 1
    body = np.empty((count, 3), dtype=np.int64)
    surface = np.empty(count, dtype=np.bool_)
    m = 0
    for i in range(shape[0]):
        for j in range(shape[1]):
            for k in range(shape[2]):
                if not occupied[i, j, k]:
                    continue
                body[m, 0] = first[0] + i
                body[m, 1] = first[1] + j
                body[m, 2] = first[2] + k
                surface[m] = not (_at(occupied, i - 1, j, k) and _at(occupied, i + 1, j, k)
                                  and _at(occupied, i, j - 1, k) and _at(occupied, i, j + 1, k)
                                  and _at(occupied, i, j, k - 1) and _at(occupied, i, j, k + 1))  # fmt: skip
                m += 1
    return body, surface


@jit
def _at(occupied, i, j, k):  # pragma: no cover (compiled)
    """Whether cell ``(i, j, k)`` is occupied; cells outside the grid are empty."""
    if i < 0 or j < 0 or k < 0 or i >= occupied.shape[0] or j >= occupied.shape[1] or k >= occupied.shape[2]:
        return False
    return occupied[i, j, k]
