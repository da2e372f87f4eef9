"""Cameras and rigs: projection geometry, the default circle, rig files and every validation error."""

import json

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.voxels.cameras import Camera, Rig, circular_rig, load_rig, look_at, save_rig


def test_projection_matches_pinhole_model():
    rot, t = look_at([1.0, 2.0, 5.0], [0.0, 1.0, 0.0])
    k = np.array([[500.0, 0.0, 319.5], [0.0, 480.0, 239.5], [0.0, 0.0, 1.0]])
    cam = Camera("c", k, rot, t, 640, 480)
    pts = np.array([[0.0, 1.0, 0.0], [0.3, 0.2, -0.5], [-1.0, 2.0, 0.5]])
    cam_pts = pts @ rot.T + t
    expected = np.stack([500 * cam_pts[:, 0] / cam_pts[:, 2] + 319.5, 480 * cam_pts[:, 1] / cam_pts[:, 2] + 239.5], 1)
    uv, depth = cam.project(pts, return_depth=True)
    assert np.allclose(uv, expected) and np.allclose(depth, cam_pts[:, 2])
    # the look-at point is on the optical axis: principal point, at its distance
    assert np.allclose(uv[0], [319.5, 239.5])
    assert np.isclose(depth[0], np.linalg.norm([1.0, 1.0, 5.0]))
    # P annihilates the centre; P X matches project
    assert np.allclose(cam.P @ np.append(cam.centre, 1.0), 0, atol=1e-9)
    assert np.allclose(cam.centre, [1.0, 2.0, 5.0])
    h = np.c_[pts, np.ones(3)] @ cam.P.T
    assert np.allclose(h[:, :2] / h[:, 2:], uv)


def test_look_at_is_upright_and_right_handed():
    rot, t = look_at([0.0, 1.0, 5.0], [0.0, 1.0, 0.0])  # looking along -Z
    cam = Camera("c", np.diag([100.0, 100.0, 1.0]), rot, t, 10, 10)
    up, right = cam.project(np.array([[0.0, 2.0, 0.0], [1.0, 1.0, 0.0]]))
    assert up[1] < 0 and abs(up[0]) < 1e-9  # world up is image up (v decreases)
    assert right[0] > 0 and abs(right[1]) < 1e-9  # facing -Z (Y up), world +X is on the camera's right
    assert np.isclose(np.linalg.det(rot), 1.0)


def test_circular_rig_geometry():
    rig = circular_rig(n=6, radius=4.0, height=2.0, focal_px=560.0, width=480, image_height=400, target=(0.5, 1.0, -1))
    assert len(rig) == 6 and rig.names == tuple(f"cam{i}" for i in range(6)) and rig.image_size == (400, 480)
    target = np.array([0.5, 1.0, -1.0])
    centres = np.array([c.centre for c in rig])
    assert np.allclose(np.hypot(centres[:, 0] - 0.5, centres[:, 2] + 1.0), 4.0)
    assert np.allclose(centres[:, 1], 2.0)
    # evenly spaced: consecutive azimuths 60 degrees apart, camera 0 on the +Z side
    azimuth = np.degrees(np.arctan2(centres[:, 0] - 0.5, centres[:, 2] + 1.0))
    assert np.allclose(np.diff(np.unwrap(np.radians(azimuth))), np.radians(60))
    assert np.isclose(azimuth[0], 0.0)
    for cam in rig:
        assert np.allclose(cam.project(target), [239.5, 199.5])
        assert cam.project(target + [0, 0.5, 0])[1] < 199.5  # upright
    assert np.allclose(rig.target, target)
    assert rig.projections.shape == (6, 3, 4)


def test_default_rig_frames_the_subject():
    """Documented framing: a cylinder of radius 0.8 m from -0.2 m to 2.4 m high is in every image with a
    margin of 20 px; a 1.75 m subject spans about half the image; a voxel of 1.75/60 m spans 3-6 px."""
    rig = circular_rig()
    theta = np.linspace(0, 2 * np.pi, 73)
    ys = np.linspace(-0.2, 2.4, 27)
    cylinder = np.array([[0.8 * np.sin(a), y, 0.8 * np.cos(a)] for a in theta for y in ys])
    height, width = rig.image_size
    for cam in rig:
        uv = cam.project(cylinder)
        assert uv.min() > 20 and uv[:, 0].max() < width - 21 and uv[:, 1].max() < height - 21
        foot, head = cam.project(np.array([[0.0, 0.0, 0.0], [0.0, 1.75, 0.0]]))
        assert 0.4 < (foot[1] - head[1]) / height < 0.6
        distance = np.linalg.norm(cam.centre - [0.0, 1.0, 0.0])
        assert 3 < cam.K[0, 0] * (1.75 / 60) / distance < 6


def test_parallel_axes_have_no_target():
    rot, t = look_at([0.0, 1.0, 5.0], [0.0, 1.0, 0.0])
    k = np.diag([100.0, 100.0, 1.0])
    rig = Rig("pair", [Camera("a", k, rot, t, 10, 10), Camera("b", k, rot, t + [1.0, 0.0, 0.0], 10, 10)])
    with pytest.raises(VoxposeError, match="parallel"):
        _ = rig.target


def test_rig_round_trip(tmp_path):
    rig = circular_rig(n=5, radius=3.3, height=1.7, focal_px=612.25, width=320, image_height=240, name="five")
    path = tmp_path / "rig.json"
    save_rig(rig, path)
    back = load_rig(path)
    assert back.name == "five" and back.names == rig.names
    for a, b in zip(rig, back, strict=True):
        assert (a.width, a.height) == (b.width, b.height)
        assert np.array_equal(a.K, b.K) and np.array_equal(a.R, b.R) and np.array_equal(a.t, b.t)
    assert not list(tmp_path.glob(".*tmp"))


def test_rig_from_intrinsic_numbers_and_look_at(tmp_path):
    rig = circular_rig(n=2)
    entries = []
    for cam in rig:
        entries.append(
            {
                "name": cam.name,
                "width": cam.width,
                "height": cam.height,
                "fx": cam.K[0, 0],
                "fy": cam.K[1, 1],
                "cx": cam.K[0, 2],
                "cy": cam.K[1, 2],
                "centre": cam.centre.tolist(),
                "look_at": [0.0, 1.0, 0.0],
            }
        )
    yaml_path = tmp_path / "rig.yaml"
    yaml_path.write_text("cameras:\n" + "".join(f"  - {json.dumps(e)}\n" for e in entries))
    back = load_rig(yaml_path)
    assert back.name == "rig"
    for a, b in zip(rig, back, strict=True):
        assert np.allclose(a.K, b.K) and np.allclose(a.R, b.R) and np.allclose(a.t, b.t)


def _camera_entry(**changes):
    cam = circular_rig(n=1)[0]
    entry = {
        "name": "cam0",
        "width": 480,
        "height": 480,
        "K": cam.K.tolist(),
        "R": cam.R.tolist(),
        "t": cam.t.tolist(),
    }
    entry.update(changes)
    return {k: v for k, v in entry.items() if v is not None}


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"K": None}, r"cameras\[0\] \(cam0\): missing key 'K'"),
        ({"width": None}, r"cameras\[0\] \(cam0\): missing key 'width'"),
        ({"t": None}, "missing key 't'"),
        ({"R": None, "t": None}, "missing key 'R' and 't'"),
        ({"K": [[1.0, 0.0], [0.0, 1.0]]}, r"K has shape \(2, 2\), expected \(3, 3\)"),
        ({"t": [0.0, 1.0]}, r"t has shape \(2,\)"),
        ({"K": [[0.0, 0.0, 1.0], [0.0, 500.0, 1.0], [0.0, 0.0, 1.0]]}, "K is degenerate"),
        ({"K": [[500.0, 0.0, 1.0], [0.0, 500.0, 1.0], [0.0, 0.0, 0.0]]}, "last row"),
        ({"R": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.1, 1.0]]}, "R is not a rotation"),
        ({"R": [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]}, "R is not a rotation"),
        ({"width": 0}, "width must be a positive integer"),
        ({"height": 480.5}, "height must be a positive integer"),
        ({"t": [0.0, float("nan"), 1.0]}, "t has non-finite values"),
        ({"center": [0.0, 1.0, 4.0]}, "unknown key 'center'"),
        ({"name": ""}, "name must be a non-empty string"),
    ],
)
def test_bad_camera_errors_name_file_camera_and_key(tmp_path, changes, message):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"cameras": [_camera_entry(**changes)]}))
    with pytest.raises(VoxposeError, match=message) as err:
        load_rig(path)
    assert str(err.value).startswith(f"{path}: ") and "\n" not in str(err.value)


def test_bad_rig_file_errors(tmp_path):
    path = tmp_path / "rig.json"
    path.write_text("{not json")
    with pytest.raises(VoxposeError, match="not a valid rig file"):
        load_rig(path)
    path.write_text(json.dumps({"name": "x"}))
    with pytest.raises(VoxposeError, match="missing key 'cameras'"):
        load_rig(path)
    path.write_text(json.dumps({"cameras": []}))
    with pytest.raises(VoxposeError, match="non-empty list"):
        load_rig(path)
    path.write_text(json.dumps({"cameras": [_camera_entry(), _camera_entry()]}))
    with pytest.raises(VoxposeError, match="duplicate camera name"):
        load_rig(path)
    path.write_text(json.dumps({"cameras": [_camera_entry(), _camera_entry(name="cam1", width=640)]}))
    with pytest.raises(VoxposeError, match="share one image size"):
        load_rig(path)
    with pytest.raises(VoxposeError, match="cannot read rig file"):
        load_rig(tmp_path / "missing.json")
    path.write_text(json.dumps({"cameras": [_camera_entry(R=None, t=None, centre=[0, 1, 0], look_at=[0, 1, 0])]}))
    with pytest.raises(VoxposeError, match="coincide"):
        load_rig(path)
