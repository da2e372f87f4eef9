"""Exact silhouettes of the ellipsoid body model (Section 6): analytic image conics, no sampled points.

An ellipsoid ``{X : (X - c)^T Sigma^-1 (X - c) <= 1}`` (``Sigma = R diag(r^2) R^T``) is the image of the
unit sphere under ``M = [[R diag(r), c], [0, 1]]``, so its dual quadric is
``Q* = M diag(1, 1, 1, -1) M^T = [[Sigma - c c^T, -c], [-c^T, -1]]``, and its outline in a camera
``P = [A | p]`` is the dual conic ``C* = P Q* P^T = A Sigma A^T - x x^T`` with ``x = P (c, 1)`` (Hartley
& Zisserman, Multiple View Geometry, 2nd ed., Section 8.3: the outline of a quadric). ``C*[2, 2]`` is
``s^2 - z^2`` with ``z`` the centre's depth and ``s`` the ellipsoid's half-extent along the optical axis,
so it is negative exactly when the ellipsoid lies wholly in front of the camera (with ``z > 0``). Scaled
to ``C*[2, 2] = -1``, ``C* = [[E - m m^T, -m], [-m^T, -1]]``: the outline is the ellipse
``{u : (u - m)^T E^-1 (u - m) <= 1}`` with centre ``m`` and symmetric positive definite ``E``. Its
bounding box is ``m +- sqrt(diag(E))``; only the pixels of that box are tested, with ``E^-1`` in closed
form. A pixel is in a silhouette when its centre (integer coordinates, ``voxpose.voxels.cameras``) lies inside
the outline of at least one ellipsoid.

A rig with lens distortion is rendered exactly too: each real pixel centre is undistorted onto the pinhole
twin (``voxpose.voxels.lens``) and tested against the conics there.

An ellipsoid that contains a camera centre or reaches behind a camera's image plane has no bounded
outline: that is a ``VoxposeError`` naming the segment and the camera (move the rig further away).
"""

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.voxels.body import Ellipsoids
from voxpose.voxels.cameras import Rig
from voxpose.voxels.lens import pinhole_twin


def image_ellipses(ellipsoids: Ellipsoids, rig: Rig):
    """Outlines of one frame's ellipsoids in every camera.

    Returns
    -------
    centres : (C, E, 2) ellipse centres in pixels.
    shapes : (C, E, 2, 2) matrices ``E``: the outline is ``(u - m)^T E^-1 (u - m) <= 1``.
    """
    if ellipsoids.n_frames != 1 or ellipsoids.centres.ndim != 2:
        raise VoxposeError("render: expected the ellipsoids of one frame (use Ellipsoids.frame(f))")
    sigma = ellipsoids.shape_matrices()  # (E, 3, 3)
    centres = ellipsoids.centres
    proj = rig.projections  # (C, 3, 4)
    a = proj[:, None, :, :3]  # (C, 1, 3, 3)
    x = np.einsum("cij,ej->cei", proj[:, :, :3], centres) + proj[:, None, :, 3]  # (C, E, 3)
    dual = a @ sigma[None] @ np.swapaxes(a, -1, -2) - x[..., :, None] * x[..., None, :]
    scale = -dual[..., 2, 2]
    bad = (scale <= 1e-12 * np.abs(dual).max(axis=(-2, -1))) | (x[..., 2] <= 0)
    if bad.any():
        c, e = np.argwhere(bad)[0]
        cam = rig.cameras[c]
        offset = cam.centre - centres[e]
        inside = offset @ np.linalg.solve(sigma[e], offset) <= 1.0
        where = "contains the centre of" if inside else "reaches behind the image plane of"
        raise VoxposeError(
            f"render: ellipsoid {ellipsoids.names[e]} {where} camera {cam.name}; "
            "the subject must lie in front of every camera"
        )
    dual = dual / scale[..., None, None]
    m = -dual[..., :2, 2]
    shapes = dual[..., :2, :2] + m[..., :, None] * m[..., None, :]
    return m, shapes


def render_silhouettes(ellipsoids: Ellipsoids, rig: Rig) -> np.ndarray:
    """Silhouettes (C, H, W) bool of one frame's body model (``Ellipsoids.frame(f)``) in every camera."""
    if rig.distorted:
        return _render_distorted(ellipsoids, rig)
    centres, shapes = image_ellipses(ellipsoids, rig)
    height, width = rig.image_size
    out = np.zeros((len(rig), height, width), dtype=bool)
    half_u = np.sqrt(shapes[..., 0, 0])
    half_v = np.sqrt(shapes[..., 1, 1])
    u0 = np.maximum(np.ceil(centres[..., 0] - half_u), 0).astype(int)
    u1 = np.minimum(np.floor(centres[..., 0] + half_u), width - 1).astype(int)
    v0 = np.maximum(np.ceil(centres[..., 1] - half_v), 0).astype(int)
    v1 = np.minimum(np.floor(centres[..., 1] + half_v), height - 1).astype(int)
    det = shapes[..., 0, 0] * shapes[..., 1, 1] - shapes[..., 0, 1] ** 2
    for c, e in np.argwhere((u1 >= u0) & (v1 >= v0)):
        du = np.arange(u0[c, e], u1[c, e] + 1) - centres[c, e, 0]
        dv = (np.arange(v0[c, e], v1[c, e] + 1) - centres[c, e, 1])[:, None]
        s = shapes[c, e]
        inside = s[1, 1] * du * du - 2.0 * s[0, 1] * dv * du + s[0, 0] * dv * dv <= det[c, e]
        out[c, v0[c, e] : v1[c, e] + 1, u0[c, e] : u1[c, e] + 1] |= inside
    return out


def _render_distorted(ellipsoids: Ellipsoids, rig: Rig) -> np.ndarray:
    """Silhouettes of a distorted rig: every real pixel centre's exact twin position tested against the conics."""
    twin = pinhole_twin(rig)
    centres, shapes = image_ellipses(ellipsoids, twin.rig)
    det = shapes[..., 0, 0] * shapes[..., 1, 1] - shapes[..., 0, 1] ** 2
    half = np.sqrt(np.stack([shapes[..., 0, 0], shapes[..., 1, 1]], axis=-1))
    out = np.zeros((len(rig),) + rig.image_size, dtype=bool)
    for c in range(len(rig)):
        u, v = twin.undistorted[c]
        for e in range(centres.shape[1]):
            du, dv = u - centres[c, e, 0], v - centres[c, e, 1]
            near = (np.abs(du) <= half[c, e, 0]) & (np.abs(dv) <= half[c, e, 1])
            if not near.any():
                continue
            s, a, b = shapes[c, e], du[near], dv[near]
            out[c][near] |= s[1, 1] * a * a - 2.0 * s[0, 1] * b * a + s[0, 0] * b * b <= det[c, e]
    return out
