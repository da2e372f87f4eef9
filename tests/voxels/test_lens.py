"""Lens distortion: OpenCV's model against planted values, its inverse, and carving/rendering of distorted rigs
against the analytic hull (``tests.helpers.exact_hull``: ray casting, no pixels)."""

import numpy as np
import pytest

from tests.helpers import as_set, exact_hull, tpose
from voxpose.voxels.body import body_ellipsoids
from voxpose.voxels.cameras import Camera, Rig, circular_rig
from voxpose.voxels.carve import Carver
from voxpose.voxels.lens import coefficients, distort, undistort
from voxpose.voxels.render import render_silhouettes

DIST = [-0.25, 0.05, 0.002, -0.001, 0.0]
WIDE = {"n": 4, "radius": 2.6, "height": 1.6, "focal_px": 90.0, "width": 128, "image_height": 128}


def distorted(rig, dist=DIST):
    return Rig(rig.name, [Camera(c.name, c.K, c.R, c.t, c.width, c.height, dist) for c in rig])


def iou(a, b):
    a, b = as_set(a), as_set(b)
    return len(a & b) / len(a | b)


def test_radial_and_tangential_terms_of_planted_points():
    # on the x axis only k1, k2, k3 and p2 act: x' = x (1 + k1 x^2 + k2 x^4 + k3 x^6) + 3 p2 x^2
    k1, k2, p1, p2, k3 = DIST
    x = 0.4
    xd, yd = distort(np.array(x), np.array(0.0), coefficients(DIST))
    assert xd == pytest.approx(x * (1 + k1 * x**2 + k2 * x**4 + k3 * x**6) + 3 * p2 * x**2)
    assert yd == pytest.approx(p1 * x**2)
    assert coefficients([0.1, 0.2]).tolist() == [0.1, 0.2, 0.0, 0.0, 0.0]


def test_undistort_inverts_distort_over_the_image():
    x, y = np.meshgrid(np.linspace(-0.7, 0.7, 21), np.linspace(-0.7, 0.7, 21))
    dist = coefficients(DIST)
    back = undistort(*distort(x, y, dist), dist)
    assert np.abs(back[0] - x).max() < 1e-9 and np.abs(back[1] - y).max() < 1e-9


def test_camera_projects_through_the_distortion():
    cam = circular_rig(n=1, focal_px=150.0, width=128, image_height=128)[0]
    bent = Camera(cam.name, cam.K, cam.R, cam.t, cam.width, cam.height, DIST)
    point = np.array([1.0, 1.8, 0.3])
    x_cam = cam.R @ point + cam.t
    xd, yd = distort(x_cam[0] / x_cam[2], x_cam[1] / x_cam[2], coefficients(DIST))
    assert np.allclose(bent.project(point), cam.K[:2, :2] @ [xd, yd] + cam.K[:2, 2])
    assert not np.allclose(bent.project(point), cam.project(point), atol=0.5)


def test_distorted_rig_carves_the_analytic_hull_and_ignoring_the_distortion_does_not():
    rig = circular_rig(**WIDE)
    bent = distorted(rig)
    body = body_ellipsoids(tpose(root_xz=(0.5, 0.3))).frame(0)  # off-centre: the distortion moves it most
    l_res = 0.04
    truth = exact_hull(body, rig, l_res, [[-1.0, -0.1, -1.0], [1.0, 2.0, 1.0]])
    sil = render_silhouettes(body, bent)
    assert not np.array_equal(sil, render_silhouettes(body, rig))
    with_dist = iou(Carver(bent, l_res)(sil), truth)
    without = iou(Carver(bent.without_distortion(), l_res)(sil), truth)
    pinhole = iou(Carver(rig, l_res)(render_silhouettes(body, rig)), truth)
    print(f"IoU with the analytic hull: pinhole rig {pinhole:.3f}, distorted rig {with_dist:.3f}, "
          f"distortion ignored {without:.3f}")
    assert with_dist > pinhole - 0.05 and with_dist > 0.8
    assert without < with_dist - 0.03


def test_a_distortion_that_folds_back_inside_the_image_is_refused():
    from voxpose.errors import VoxposeError
    from voxpose.voxels.lens import PinholeTwin

    with pytest.raises(VoxposeError, match="cannot be inverted"):
        PinholeTwin(distorted(circular_rig(**WIDE), [-0.9, 0.0]))


def _file_cameras(rig, scale, rot, floor):
    """Cameras of ``rig`` written in a world X_file with voxpose's world = scale (rot X_file - floor e_y)."""
    out = []
    for cam in rig:
        r = cam.R @ rot
        t = (cam.t - cam.R @ np.array([0.0, scale * floor, 0.0])) / scale
        out.append({"name": cam.name, "width": cam.width, "height": cam.height, "K": cam.K.tolist(),
                    "dist": DIST, "R": r.tolist(), "t": t.tolist()})  # fmt: skip
    return out


@pytest.mark.parametrize("unit, scale, up, floor", [("mm", 1e-3, "+z", 35.0), ("dm", 0.1, "-y", -2.0),
                                                     (0.0254, 0.0254, "-z", 0.0)])  # fmt: skip
def test_unit_and_up_axis_give_the_same_cameras_in_a_y_up_metric_world(tmp_path, unit, scale, up, floor):
    import json

    from voxpose.voxels.cameras import load_rig

    rig = distorted(circular_rig(**WIDE))
    axis = {"+z": [0, 0, 1], "-y": [0, -1, 0], "-z": [0, 0, -1]}[up]
    rot = np.array({"+z": [[1, 0, 0], [0, 0, 1], [0, -1, 0]], "-y": [[1, 0, 0], [0, -1, 0], [0, 0, -1]],
                    "-z": [[1, 0, 0], [0, 0, -1], [0, 1, 0]]}[up], dtype=float)  # fmt: skip
    assert np.allclose(rot @ axis, [0, 1, 0]) and np.isclose(np.linalg.det(rot), 1)
    path = tmp_path / "studio.json"
    cameras = _file_cameras(rig, scale, rot, floor)
    path.write_text(json.dumps({"unit": unit, "up": up, "floor": floor, "cameras": cameras}))
    loaded = load_rig(path)
    points = np.random.default_rng(0).uniform([-0.8, 0, -0.8], [0.8, 2, 0.8], (50, 3))
    for a, b in zip(rig, loaded, strict=True):
        assert np.allclose(a.project(points), b.project(points), atol=1e-6)
        assert np.allclose(b.dist, a.dist)
    world = np.eye(4)
    world[:3, :3] = rot
    world[1, 3] = -floor
    path.write_text(json.dumps({"unit": unit, "world": world.tolist(), "cameras": cameras}))
    for a, b in zip(rig, load_rig(path), strict=True):
        assert np.allclose(a.project(points), b.project(points), atol=1e-6)


def test_a_rig_without_the_new_keys_loads_bit_for_bit(tmp_path):
    import json

    from voxpose.voxels.cameras import load_rig, rig_json, save_rig

    rig = circular_rig()
    save_rig(rig, tmp_path / "rig.json")
    loaded = load_rig(tmp_path / "rig.json")
    assert not loaded.distorted and rig_json(loaded) == rig_json(rig)
    for a, b in zip(rig, loaded, strict=True):
        assert a.K.tobytes() == b.K.tobytes() and a.R.tobytes() == b.R.tobytes() and a.t.tobytes() == b.t.tobytes()
    data = json.loads(rig_json(rig)) | {"unit": "m", "up": "+y", "floor": 0.0}  # the defaults, spelt out
    (tmp_path / "explicit.json").write_text(json.dumps(data))
    assert rig_json(load_rig(tmp_path / "explicit.json")) == rig_json(rig)
    save_rig(distorted(rig), tmp_path / "bent.json")
    assert np.array_equal(load_rig(tmp_path / "bent.json")[0].dist, coefficients(DIST))


def test_rotations_printed_to_few_digits_are_reorthonormalised_and_worse_ones_refused(caplog):
    from voxpose.errors import VoxposeError

    cam = circular_rig(n=1)[0]
    rounded = np.round(cam.R, 5)  # off by up to 1e-5
    assert np.abs(rounded @ rounded.T - np.eye(3)).max() > 1e-6
    with caplog.at_level("INFO"):
        fixed = Camera("c", cam.K, rounded, cam.t, cam.width, cam.height)
    assert np.abs(fixed.R @ fixed.R.T - np.eye(3)).max() < 1e-12 and np.abs(fixed.R - cam.R).max() < 1e-5
    assert "nearest rotation" in caplog.text
    with pytest.raises(VoxposeError, match="not a rotation"):
        Camera("c", cam.K, cam.R * (1 + 2e-4), cam.t, cam.width, cam.height)


def test_distorted_carving_equals_testing_every_voxel_at_its_distorted_pixel():
    from tests.helpers import box_voxels

    bent = distorted(circular_rig(**WIDE))
    body = body_ellipsoids(tpose(root_xz=(0.3, -0.2))).frame(0)
    sil = render_silhouettes(body, bent)
    l_res, bounds = 0.05, [[-1.2, -0.2, -1.2], [1.2, 2.2, 1.2]]
    ijk = box_voxels(bounds, l_res)
    centres = (ijk + 0.5) * l_res
    inside = np.ones(len(ijk), dtype=bool)
    for c, cam in enumerate(bent):
        (u, v), z = np.moveaxis(cam.project(centres), -1, 0), cam.project(centres, return_depth=True)[1]
        col, row = np.floor(u + 0.5).astype(int), np.floor(v + 0.5).astype(int)
        ok = (z > 0) & (col >= 0) & (col < cam.width) & (row >= 0) & (row < cam.height)
        inside &= ok & sil[c][np.clip(row, 0, cam.height - 1), np.clip(col, 0, cam.width - 1)]
    assert inside.sum() > 100
    assert as_set(Carver(bent, l_res, bounds=bounds)(sil)) == as_set(ijk[inside])
