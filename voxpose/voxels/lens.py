"""Lens distortion (OpenCV's model) and the pinhole twin through which distorted rigs are carved and rendered.

Model (OpenCV ``projectPoints``): a camera-frame point ``(X, Y, Z)`` has normalised coordinates
``x = X / Z``, ``y = Y / Z``; with ``r^2 = x^2 + y^2`` and coefficients ``(k1, k2, p1, p2, k3)`` it is seen at

    x' = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
    y' = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y

and then at pixel ``K (x', y', 1)``. A calibration with 2, 3 or 4 coefficients gives the leading ones; the
rest are 0. ``undistort`` inverts the map by Newton's method.

Pinhole twin. Carving (``voxels.carve``, exact only for straight-line projections) and the analytic silhouettes
of the body model (``voxels.render``, conics) need pinhole cameras. A distorted rig is therefore handled
through its twin: the same K, R and t without distortion, on a canvas enlarged by a margin so that it holds
every ray the real image sees (the undistorted image border). Each twin pixel centre is distorted to the real
image and takes the nearest real pixel (``to_twin``: the carving's coarse levels, made conservative in
``voxels.carve``); each real pixel centre has its exact position on the twin (``undistorted``: the rendering
tests it against the conics there). Points whose rays the real image does not see (outside it, or beyond 1.05
times the largest undistorted radius of its border, where the polynomial may fold back) are background.
"""

from dataclasses import replace

import numpy as np

from voxpose.errors import VoxposeError

N_COEFFICIENTS = 5
_UNDISTORT_ITERATIONS = 20
_FOLD_MARGIN = 1.05
_twin_cache: dict = {}


def coefficients(values) -> np.ndarray:
    """(5,) ``(k1, k2, p1, p2, k3)`` from 2 to 5 given coefficients (the missing ones 0)."""
    array = np.asarray(values, dtype=float).reshape(-1)
    if not 2 <= array.size <= N_COEFFICIENTS:
        raise VoxposeError(f"dist must hold 2 to 5 coefficients (k1 k2 [p1 p2 [k3]]), got {array.size}")
    if not np.isfinite(array).all():
        raise VoxposeError("dist has non-finite values")
    return np.concatenate([array, np.zeros(N_COEFFICIENTS - array.size)])


def distort(x, y, dist):
    """Distorted normalised coordinates (x', y') of normalised coordinates (x, y) (module docstring)."""
    k1, k2, p1, p2, k3 = dist
    r2 = x * x + y * y
    radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
    return (x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
            y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y)  # fmt: skip


def undistort(xd, yd, dist):
    """Normalised coordinates whose distortion is (xd, yd): Newton's method from (xd, yd) (OpenCV's fixed-point
    iteration diverges for strong wide-angle lenses)."""
    k1, k2, p1, p2, k3 = dist
    x, y = np.array(xd, dtype=float), np.array(yd, dtype=float)
    for _ in range(_UNDISTORT_ITERATIONS) if np.any(dist) else ():
        r2 = x * x + y * y
        radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
        slope = k1 + r2 * (2 * k2 + 3 * k3 * r2)  # d radial / d r^2
        fx, fy = distort(x, y, dist)
        fx, fy = fx - xd, fy - yd
        a = radial + 2 * x * x * slope + 2 * p1 * y + 6 * p2 * x
        b = 2 * x * y * slope + 2 * p1 * x + 2 * p2 * y
        d = radial + 2 * y * y * slope + 6 * p1 * y + 2 * p2 * x
        det = a * d - b * b
        x, y = x - (d * fx - b * fy) / det, y - (a * fy - b * fx) / det
    return x, y


def _normalised(k, u, v):
    """Normalised coordinates of pixels (u, v) of intrinsics ``k`` (upper triangular)."""
    y = (v - k[1, 2]) / k[1, 1]
    return (u - k[0, 2] - k[0, 1] * y) / k[0, 0], y


def _pixels(k, x, y):
    return k[0, 0] * x + k[0, 1] * y + k[0, 2], k[1, 1] * y + k[1, 2]


def _border(width, height):
    """Pixel coordinates of the image border (the pixel squares' outer edges), one point per pixel."""
    us = np.arange(width + 1) - 0.5
    vs = np.arange(height + 1) - 0.5
    u = np.concatenate([us, us, np.full_like(vs, -0.5), np.full_like(vs, width - 0.5)])
    v = np.concatenate([np.full_like(us, -0.5), np.full_like(us, height - 0.5), vs, vs])
    return u, v


class PinholeTwin:
    """The pinhole twin of a rig (module docstring): ``rig`` (undistorted, enlarged canvas) and the lookups."""

    def __init__(self, rig):
        height, width = rig.image_size
        bu, bv = _border(width, height)
        undist, radii = [], []
        for cam in rig.cameras:
            xd, yd = _normalised(cam.K, bu, bv)
            x, y = undistort(xd, yd, cam.dist)
            back = distort(x, y, cam.dist)
            miss = np.nanmax(np.hypot(back[0] - xd, back[1] - yd)) * cam.K[0, 0] if np.isfinite(x + y).all() else np.inf
            if not miss < 1e-3:
                raise VoxposeError(f"camera {cam.name}: the distortion {cam.dist.tolist()} cannot be inverted at the "
                                   "image border (the polynomial folds back inside the image)")  # fmt: skip
            undist.append(_pixels(cam.K, x, y))
            radii.append(np.sqrt(x * x + y * y).max() * _FOLD_MARGIN)
        lo_u = min(u.min() for u, _ in undist)
        hi_u = max(u.max() for u, _ in undist)
        lo_v = min(v.min() for _, v in undist)
        hi_v = max(v.max() for _, v in undist)
        left, top = max(0, int(np.ceil(-0.5 - lo_u))), max(0, int(np.ceil(-0.5 - lo_v)))
        right = max(0, int(np.ceil(hi_u - (width - 0.5))))
        bottom = max(0, int(np.ceil(hi_v - (height - 0.5))))
        self.offset = np.array([top, left])  # (row, column) of the real image's pixel (0, 0) on the twin canvas
        self.size = (height + top + bottom, width + left + right)
        cameras = []
        for cam in rig.cameras:
            k = cam.K.copy()
            k[0, 2] += left
            k[1, 2] += top
            cameras.append(replace(cam, K=k, width=self.size[1], height=self.size[0], dist=None))
        self.rig = replace(rig, cameras=cameras)
        self._cameras = [(twin.K, cam.dist, cam.K, r) for twin, cam, r in zip(cameras, rig.cameras, radii,
                                                                               strict=True)]  # fmt: skip
        self._to_twin = np.stack([self._twin_lookup(cam, twin.K, r, width, height)
                                  for cam, twin, r in zip(rig.cameras, cameras, radii, strict=True)])  # fmt: skip
        self.undistorted = np.stack([self._undistorted(cam, twin.K) for cam, twin in zip(rig.cameras, cameras,
                                                                                         strict=True)])  # fmt: skip

    def _twin_lookup(self, cam, twin_k, max_radius, width, height):
        """Flat index into the real image of every twin pixel (-1: not seen by the real image)."""
        rows, cols = np.indices(self.size, dtype=float)
        x, y = _normalised(twin_k, cols, rows)
        u, v = _pixels(cam.K, *distort(x, y, cam.dist))
        col, row = np.floor(u + 0.5), np.floor(v + 0.5)
        ok = (x * x + y * y <= max_radius**2) & (col >= 0) & (col < width) & (row >= 0) & (row < height)
        return np.where(ok, row * width + col, -1).astype(np.int64).reshape(-1)

    def _undistorted(self, cam, twin_k):
        """(2, H, W) twin pixel coordinates (u, v) of every real pixel centre."""
        rows, cols = np.indices((cam.height, cam.width), dtype=float)
        return np.stack(_pixels(twin_k, *undistort(*_normalised(cam.K, cols, rows), cam.dist)))

    def distort_pixels(self, u, v):
        """Real-image pixel coordinates of twin pixel coordinates (C, N) each (rows: cameras)."""
        out_u, out_v = np.empty_like(u), np.empty_like(v)
        for c, (twin, dist, k, max_radius) in enumerate(self._cameras):
            x, y = _normalised(twin, u[c], v[c])
            uu, vv = _pixels(k, *distort(x, y, dist))
            seen = x * x + y * y <= max_radius**2  # beyond it the polynomial may fold back into the image
            out_u[c], out_v[c] = np.where(seen, uu, np.nan), np.where(seen, vv, np.nan)
        return out_u, out_v

    def to_twin(self, sil: np.ndarray) -> np.ndarray:
        """Real silhouettes (C, H, W) bool -> twin silhouettes (C, H', W')."""
        flat = sil.reshape(len(sil), -1)
        index = self._to_twin
        out = np.take_along_axis(flat, np.maximum(index, 0), axis=1) & (index >= 0)
        return out.reshape((len(sil),) + self.size)



def pinhole_twin(rig) -> PinholeTwin:
    """The (cached) pinhole twin of a rig with distortion."""
    key = tuple((c.P.tobytes(), c.dist.tobytes(), c.width, c.height) for c in rig.cameras)
    if key not in _twin_cache:
        _twin_cache.clear()  # one rig at a time is the common case; keeps memory bounded
        _twin_cache[key] = PinholeTwin(rig)
    return _twin_cache[key]
