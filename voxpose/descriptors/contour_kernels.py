"""Compiled (numba) kernel of the contour's farthest-point sampling
(:func:`voxpose.descriptors.contour.farthest_points`), selected by :mod:`voxpose.kernels`.

The numpy path makes two passes over the m boundary points per sampled point (``argmax``, then ``np.minimum`` of
the new squared distances), each through temporaries; here one pass updates the distances and finds the next
farthest point. The arithmetic is the same (``dx * dx + dy * dy`` in float64, the smaller distance kept, the first
largest chosen), so the indices are the numpy path's exactly, ties included (``tests/descriptors/test_contour.py``).
"""

import numpy as np

from voxpose.kernels import jit


@jit
def farthest(x, y, chosen):  # pragma: no cover - compiled; the numpy path is the reference
    """Fill ``chosen`` (n,) with farthest-point samples of the points (``x``, ``y``), the first being point 0."""
    m = x.shape[0]
    dist = np.empty(m)
    best, largest = 0, -1.0
    for k in range(m):
        dx = x[k] - x[0]
        dy = y[k] - y[0]
        dist[k] = dx * dx + dy * dy
        if dist[k] > largest:
            best, largest = k, dist[k]
    chosen[0] = 0
    for i in range(1, chosen.shape[0]):
        j = best
        chosen[i] = j
        best, largest = 0, -1.0
        for k in range(m):
            dx = x[k] - x[j]
            dy = y[k] - y[j]
            d = dx * dx + dy * dy
            if d < dist[k]:
                dist[k] = d
            if dist[k] > largest:
                best, largest = k, dist[k]
