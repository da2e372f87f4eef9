"""Compiled (numba) kernels of the visual-hull carving (:mod:`voxpose.voxels.carve`), selected by
:mod:`voxpose.kernels`.

The numpy path carves a frame in a few dozen array operations per octree level on arrays of a few thousand
cells, so most of its time is per-call overhead and temporaries. These loops do the same arithmetic, in the
same order, on the same projections (computed by ``Carver._project`` in both paths), so their decisions are
the numpy path's bit for bit (``tests/voxels/test_carve_kernels.py``):

- :func:`summed_areas_fill`: the summed-area table of each silhouette's crop (integer sums: exact);
- :func:`cell_views`: each octree cell's pixel window per camera and its pixel count in the tables;
- :func:`voxel_occupied`: each voxel centre's pixel in every silhouette, stopping at the first view too many
  that misses.
"""

import math

import numpy as np

from voxpose.kernels import jit


@jit
def summed_areas_fill(sil, offsets, limits, base, flat):  # pragma: no cover (compiled)
    """Fill ``flat`` with camera c's table ``T[r, k]`` (pixels of the crop's rows < r, columns < k), row stride
    ``limits[c, 1] + 1``, from ``base[c]`` (``carve._summed_areas`` layout; empty crops stay 0)."""
    for c in range(sil.shape[0]):
        rows, cols = limits[c, 0], limits[c, 1]
        stride = cols + 1
        start = base[c]
        r0, c0 = offsets[c, 0], offsets[c, 1]
        for r in range(rows):
            run = 0
            above = start + r * stride
            here = above + stride
            for k in range(cols):
                run += sil[c, r0 + r, c0 + k]
                flat[here + k + 1] = flat[above + k + 1] + run


@jit
def _hits(flat, base, offsets, limits, cam, u0, u1, v0, v1):  # pragma: no cover (compiled)
    """Pixels of the window columns ``u0 .. u1 - 1``, rows ``v0 .. v1 - 1`` (image) in camera ``cam``'s table."""
    c0 = np.int64(min(max(u0 - offsets[cam, 1], 0.0), limits[cam, 1]))
    c1 = np.int64(min(max(u1 - offsets[cam, 1], 0.0), limits[cam, 1]))
    r0 = np.int64(min(max(v0 - offsets[cam, 0], 0.0), limits[cam, 0]))
    r1 = np.int64(min(max(v1 - offsets[cam, 0], 0.0), limits[cam, 0]))
    stride = limits[cam, 1] + 1
    r0 = r0 * stride + base[cam]
    r1 = r1 * stride + base[cam]
    return flat[r1 + c1] - flat[r0 + c1] - flat[r1 + c0] + flat[r0 + c0]


@jit
def cell_views(u, v, z, rho, p3norm, aa, ap, bb, bp, pp, flat, base, offsets, limits, same, full_flat, full_base,
               full_offsets, full_limits, max_misses):  # fmt: skip  # pragma: no cover (compiled)
    """``(maybe, full)`` (N,) of ``Carver._cell_views`` from the cells' centre projections ``u, v, z`` (C, N);
    ``same``: the full tables are the tables (no lens distortion). A cell stops at the first camera too many
    (more than ``max_misses``) that cannot see it: its counts are then those so far, too few either way (a
    camera that surely sees the cell also may), so every decision is the numpy path's."""
    n_cams, n = u.shape
    maybe = np.zeros(n, dtype=np.int64)
    full = np.zeros(n, dtype=np.int64)
    for i in range(n):
        for cam in range(n_cams):
            if cam - maybe[i] > max_misses:
                break
            near = z[cam, i] - rho * p3norm[cam]
            front = near > 0
            scale = rho / (near if front else 1.0)
            uc = u[cam, i] if front else 0.0
            vc = v[cam, i] if front else 0.0
            ru = scale * math.sqrt(max(aa[cam] - 2 * uc * ap[cam] + uc * uc * pp[cam], 0.0))
            rv = scale * math.sqrt(max(bb[cam] - 2 * vc * bp[cam] + vc * vc * pp[cam], 0.0))
            u0 = np.floor(uc - ru + 0.5)  # floats, as in numpy: a window may reach far beyond the image
            u1 = np.floor(uc + ru + 1.5)
            v0 = np.floor(vc - rv + 0.5)
            v1 = np.floor(vc + rv + 1.5)
            hits = _hits(flat, base, offsets, limits, cam, u0, u1, v0, v1)
            if not front or hits > 0:
                maybe[i] += 1
            if not same:
                hits = _hits(full_flat, full_base, full_offsets, full_limits, cam, u0, u1, v0, v1)
            if front and hits == (u1 - u0) * (v1 - v0):
                full[i] += 1
    return maybe, full


@jit
def voxel_occupied(u, v, z, images, width, height, max_misses):  # pragma: no cover (compiled)
    """(N,) bool: the voxel centres projecting to ``u, v, z`` (C, N) inside all but ``max_misses`` silhouettes
    ``images`` (C, H * W)."""
    n_cams, n = u.shape
    occupied = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        misses = 0
        for cam in range(n_cams):
            col = np.floor(u[cam, i] + 0.5)
            row = np.floor(v[cam, i] + 0.5)
            if not (z[cam, i] > 0 and col >= 0 and col < width and row >= 0 and row < height
                    and images[cam, np.int64(row * width + col)]):  # fmt: skip
                misses += 1
                if misses > max_misses:
                    break
        occupied[i] = misses <= max_misses
    return occupied
