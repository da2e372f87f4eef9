"""2D shape contexts on silhouette contours: the image descriptor of Agarwal & Triggs (CVPR 2004, PAMI 2006).

The paper's Table 1 compares against Agarwal & Triggs, who describe one silhouette by shape contexts
(Belongie, Malik & Puzicha, PAMI 2002) at a few hundred points of its contour, vector-quantise them into a
100-bin soft histogram and regress pose with an RVM. This module gives the per-image part:

- ``contour_points``: the silhouette's boundary pixels (silhouette pixels with a 4-neighbour outside it or on the
  image border), thinned to ``n_points`` roughly evenly spaced points by farthest-point sampling started at the
  first boundary pixel in raster order (deterministic, no random draws; all boundary pixels if there are fewer).
- ``shape_contexts``: at each point, the histogram of the other points' offsets in ``n_r`` log-spaced radial
  bins from ``r_inner`` to ``r_outer`` times the mean pairwise distance (scale invariance; Belongie's 1/8 and 2)
  and ``n_theta`` angular bins. Angles are absolute image directions, ``atan2(dy, dx)`` in image coordinates
  (x right, y down) over [0, 360) degrees from +x, so rotating the image by one bin width (30 degrees at 12
  bins) shifts every histogram by one angular bin: rotation-equivariant, not invariant, as in A&T, for whom
  the silhouette's orientation carries pose. Offsets outside [r_inner, r_outer) do not vote. Bin index
  ``i_r * n_theta + i_theta``; each histogram is divided by the number of other points, so it does not depend
  on ``n_points``.
"""

import numpy as np

from voxpose.descriptors import contour_kernels
from voxpose.errors import VoxposeError
from voxpose.kernels import use_numba


def boundary_pixels(mask: np.ndarray) -> np.ndarray:
    """(m, 2) float (x, y) = (column, row) of the pixels of a (H, W) bool mask on its boundary, raster order."""
    mask = np.asarray(mask, dtype=bool)
    if mask.ndim != 2:
        raise VoxposeError(f"contour: expected a 2-D mask, got shape {mask.shape}")
    rows_any, cols_any = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    if rows_any.size == 0:
        return np.zeros((0, 2))
    r0, c0 = rows_any[0], cols_any[0]
    crop = mask[r0 : rows_any[-1] + 1, c0 : cols_any[-1] + 1]  # the work scales with the silhouette
    padded = np.pad(crop, 1)
    interior = padded[:-2, 1:-1] & padded[2:, 1:-1] & padded[1:-1, :-2] & padded[1:-1, 2:]
    rows, cols = np.nonzero(crop & ~interior)
    return np.stack([cols + c0, rows + r0], axis=1).astype(float)


def farthest_points(points: np.ndarray, n: int) -> np.ndarray:
    """Indices of ``n`` of ``points`` (m, 2) by farthest-point sampling from the first (all if m <= n)."""
    m = len(points)
    if m <= n:
        return np.arange(m)
    x, y = np.ascontiguousarray(points[:, 0]), np.ascontiguousarray(points[:, 1])
    chosen = np.empty(n, dtype=np.intp)
    if use_numba():  # the same indices in one pass per point (voxpose.descriptors.contour_kernels)
        contour_kernels.farthest(x, y, chosen)
        return np.sort(chosen)
    chosen[0] = 0
    dist = (x - x[0]) ** 2 + (y - y[0]) ** 2
    for i in range(1, n):
        j = chosen[i] = int(dist.argmax())
        dx, dy = x - x[j], y - y[j]
        np.minimum(dist, dx * dx + dy * dy, out=dist)
    return np.sort(chosen)


def contour_points(mask: np.ndarray, n_points: int) -> np.ndarray:
    """(n, 2) points (x, y) sampled evenly on the boundary of a silhouette (module docstring)."""
    points = boundary_pixels(mask)
    return points[farthest_points(points, n_points)]


def shape_contexts(points, *, n_r: int = 5, n_theta: int = 12, r_inner: float = 0.125, r_outer: float = 2.0):
    """Shape contexts (n, n_r * n_theta) of 2D ``points`` (n, 2) (module docstring); n < 2 gives (n, bins) zeros."""
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 2 or not np.isfinite(points).all():
        raise VoxposeError(f"shape contexts: points must be finite (n, 2), got shape {points.shape}")
    if n_r < 1 or n_theta < 1 or not 0 < r_inner < r_outer:
        raise VoxposeError(f"shape contexts: need n_r, n_theta >= 1 and 0 < r_inner < r_outer, got "
                           f"{n_r}, {n_theta}, {r_inner}, {r_outer}")  # fmt: skip
    n = len(points)
    out = np.zeros((n, n_r * n_theta))
    if n < 2:
        return out
    x, y = np.ascontiguousarray(points[:, 0]), np.ascontiguousarray(points[:, 1])
    dx, dy = x[None, :] - x[:, None], y[None, :] - y[:, None]  # d[i, j] = p_j - p_i, each coordinate contiguous
    r = np.hypot(dx, dy)
    off = ~np.eye(n, dtype=bool)
    scale = r[off].mean()
    if scale <= 0:
        return out
    edges = np.geomspace(r_inner, r_outer, n_r + 1) * scale
    i_r = np.searchsorted(edges, r, side="right") - 1
    theta = np.arctan2(dy, dx)  # in [-pi, pi]: to [0, 2 pi) as np.mod(theta, 2 pi) does, at a third of its cost
    theta = np.where(theta < 0, theta + 2 * np.pi, theta)
    i_t = np.minimum((theta * (n_theta / (2 * np.pi))).astype(np.intp), n_theta - 1)
    vote = off & (i_r >= 0) & (i_r < n_r)
    flat = (np.arange(n)[:, None] * (n_r * n_theta) + i_r * n_theta + i_t)[vote]
    return np.bincount(flat, minlength=out.size).reshape(out.shape) / (n - 1)
