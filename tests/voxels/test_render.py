"""Exact silhouettes against brute-force ray casting through every pixel centre."""

import numpy as np
import pytest

from tests.helpers import tpose, walk_motion
from voxpose.errors import VoxposeError
from voxpose.motion.rotations import axis_angle_to_matrix
from voxpose.voxels.body import Ellipsoids, body_ellipsoids
from voxpose.voxels.cameras import Camera, Rig, circular_rig, look_at
from voxpose.voxels.render import image_ellipses, render_silhouettes


def ray_cast(ellipsoids: Ellipsoids, rig: Rig) -> np.ndarray:
    """(C, H, W): does the ray through each pixel centre hit an ellipsoid in front of the camera?"""
    height, width = rig.image_size
    v, u = np.mgrid[0:height, 0:width].astype(float)
    pix = np.stack([u.ravel(), v.ravel(), np.ones(u.size)], axis=1)
    out = []
    for cam in rig:
        rays = np.linalg.solve(cam.K, pix.T).T @ cam.R  # world directions (rows): R^T K^-1 (u, v, 1)
        hit = np.zeros(len(pix), dtype=bool)
        for c, rot, r in zip(ellipsoids.centres, ellipsoids.rotations, ellipsoids.radii, strict=True):
            o = (rot.T @ (cam.centre - c)) / r  # in the frame where the ellipsoid is the unit sphere
            d = (rays @ rot) / r
            a, b, cc = (d * d).sum(1), d @ o, o @ o
            hit |= (b * b - a * (cc - 1.0) >= 0) & (b < 0)  # real roots, in front (camera is outside)
        out.append(hit.reshape(height, width))
    return np.stack(out)


def small_rig():
    return circular_rig(n=3, radius=4.0, height=2.0, focal_px=200.0, width=160, image_height=180)


@pytest.mark.parametrize("make", [lambda: tpose(), lambda: walk_motion(3)])
def test_body_silhouettes_match_ray_casting(make):
    motion = make()
    rig = small_rig()
    el = body_ellipsoids(motion)
    for f in range(motion.n_frames):
        frame = el.frame(f)
        fast, truth = render_silhouettes(frame, rig), ray_cast(frame, rig)
        assert fast.shape == truth.shape == (3, 180, 160)
        assert truth.sum() > 3000  # the subject is in view
        assert (fast == truth).mean() >= 0.999


def test_random_ellipsoids_with_a_general_camera():
    rng = np.random.default_rng(3)
    n = 12
    axes = rng.normal(size=(n, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    rotations = axis_angle_to_matrix(axes, rng.uniform(0, np.pi, n))
    el = Ellipsoids(
        tuple(f"e{i}" for i in range(n)),
        rng.uniform(-0.8, 0.8, (n, 3)),
        rotations,
        rng.uniform(0.05, 0.4, (n, 3)),
    )
    rot, t = look_at([2.5, 2.0, 3.0], [0.1, 0.0, -0.2], up=(0.2, 1.0, 0.1))
    k = np.array([[230.0, 3.0, 70.2], [0.0, 210.0, 95.7], [0.0, 0.0, 1.0]])  # skew, off-centre principal point
    rig = Rig("general", [Camera("g", k, rot, t, 150, 190)])
    fast, truth = render_silhouettes(el, rig), ray_cast(el, rig)
    assert truth.sum() > 2000 and (~truth).sum() > 2000
    assert (fast == truth).mean() >= 0.999


def test_sphere_outline_is_the_analytic_ellipse():
    # a sphere of radius r at distance D on the optical axis: a circle of radius f r / sqrt(D^2 - r^2)
    rig = Rig("one", [Camera("c", np.diag([300.0, 300.0, 1.0]), *look_at([0.0, 0.0, 5.0], [0.0, 0.0, 0.0]), 5, 5)])
    el = Ellipsoids(("s",), np.zeros((1, 3)), np.eye(3)[None], np.full((1, 3), 0.6))
    centres, shapes = image_ellipses(el, rig)
    radius = 300.0 * 0.6 / np.sqrt(25.0 - 0.36)
    assert np.allclose(centres[0, 0], 0.0) and np.allclose(shapes[0, 0], radius**2 * np.eye(2))


def _one(centre, radius=0.3):
    return Ellipsoids(("blob",), np.array([centre], float), np.eye(3)[None], np.full((1, 3), radius))


def test_ellipsoids_that_cannot_be_rendered():
    rig = small_rig()
    cam = rig[1]
    with pytest.raises(VoxposeError, match="ellipsoid blob contains the centre of camera cam1"):
        render_silhouettes(_one(cam.centre + [0.05, 0.0, 0.0]), rig)
    side = np.cross(cam.forward, [0.0, 1.0, 0.0])
    beside = cam.centre + 0.5 * side / np.linalg.norm(side)  # straddles cam1's image plane
    with pytest.raises(VoxposeError, match="reaches behind the image plane of camera cam1"):
        render_silhouettes(_one(beside), rig)
    behind = cam.centre - 1.0 * cam.forward
    with pytest.raises(VoxposeError, match="reaches behind the image plane of camera cam1"):
        render_silhouettes(_one(behind), Rig("one", [cam]))
    with pytest.raises(VoxposeError, match="one frame"):
        render_silhouettes(body_ellipsoids(tpose(2)), rig)


def test_out_of_view_ellipsoid_leaves_images_empty():
    rig = small_rig()
    far = _one([0.0, 6.0, 0.0], 0.2)  # 59 degrees above the optical axes: in front, out of view
    assert not render_silhouettes(far, rig).any()
