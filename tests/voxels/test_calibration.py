"""``voxpose rig import``: OpenCV FileStorage YAML/XML (per camera or one file) and projection matrices give the
cameras they were written from; what cannot be read is one line naming the file and key."""

import json

import numpy as np
import pytest

from tests.studio import Z_UP, distorted, opencv_yaml
from voxpose.cli.main import main
from voxpose.voxels.cameras import circular_rig, load_rig

RIG = distorted(circular_rig(n=4, focal_px=150.0, width=128, image_height=128, name="four"))
POINTS = np.random.default_rng(1).uniform([-0.8, 0.0, -0.8], [0.8, 2.0, 0.8], (40, 3))


def same_cameras(loaded, rig=RIG, atol=1e-6):
    assert loaded.names == rig.names
    for a, b in zip(rig, loaded, strict=True):
        assert np.allclose(a.project(POINTS), b.project(POINTS), atol=atol)


def run(*args):
    return main([str(a) for a in args])


def _xml(cam):
    def matrix(tag, array):
        array = np.atleast_2d(array)
        data = " ".join(f"{v:.17g}" for v in array.reshape(-1))
        return (f'<{tag} type_id="opencv-matrix"><rows>{array.shape[0]}</rows><cols>{array.shape[1]}</cols>'
                f"<dt>d</dt><data>{data}</data></{tag}>")  # fmt: skip

    rot = cam.R @ Z_UP
    return (f"<{cam.name}><image_width>{cam.width}</image_width><image_height>{cam.height}</image_height>"
            + matrix("CameraMatrix", cam.K) + matrix("DistortionCoeffs", cam.dist[:4]) + matrix("R", rot)
            + matrix("T", 1000 * cam.t[:, None]) + f"</{cam.name}>")  # fmt: skip


def test_opencv_yaml_per_camera_in_mm_with_z_up(tmp_path):
    files = []
    for cam in RIG:
        files.append(tmp_path / f"{cam.name}.yaml")
        files[-1].write_text(opencv_yaml(cam))
    assert run("rig", "import", *files, "--unit", "mm", "--up", "+z", "--floor", 0, "-o", tmp_path / "rig.json") == 0
    same_cameras(load_rig(tmp_path / "rig.json"))


def test_one_opencv_xml_for_all_cameras_with_four_coefficients(tmp_path):
    rig = distorted(circular_rig(n=4, focal_px=150.0, width=128, image_height=128), [-0.2, 0.03, 0.001, 0.002])
    path = tmp_path / "studio.xml"
    path.write_text('<?xml version="1.0"?>\n<opencv_storage>' + "".join(_xml(c) for c in rig) + "</opencv_storage>")
    assert run("rig", "import", path, "--unit", "mm", "--up", "+z", "--floor", 0, "-o", tmp_path / "rig.json") == 0
    same_cameras(load_rig(tmp_path / "rig.json"), rig)


def test_projection_matrices_in_decimetres_with_y_down(tmp_path):
    plain = circular_rig(n=4, focal_px=150.0, width=128, image_height=128)
    flip = np.diag([1.0, -1.0, -1.0])  # studio (Y down, dm) -> voxpose: X = 0.1 flip X_studio, floor at y = 0
    lines = []
    for cam in plain:
        p = cam.K @ np.hstack([cam.R @ flip.T, 10.0 * cam.t[:, None]]) * 3.7  # any scale of P
        lines += [" ".join(f"{v:.17g}" for v in row) for row in p] + [""]
    (tmp_path / "p.txt").write_text("# P per camera\n" + "\n".join(lines))
    out = tmp_path / "rig.json"
    assert run("rig", "import", tmp_path / "p.txt", "--projections", "--size", "128x128", "--unit", "dm",
               "--up=-y", "--floor", 0, "-o", out) == 0  # fmt: skip
    same_cameras(load_rig(out), plain)


def test_the_floor_is_estimated_from_a_carved_frame(tmp_path):
    from tests.helpers import tpose
    from voxpose.voxels.body import body_ellipsoids
    from voxpose.voxels.render import render_silhouettes
    from voxpose.voxels.silhouettes import write_silhouette_folder

    write_silhouette_folder([render_silhouettes(body_ellipsoids(tpose()).frame(0), RIG)], RIG, tmp_path / "sil")
    from voxpose.voxels.cameras import Camera

    shifted = []
    for cam in RIG:  # the studio's origin 400 mm above the floor: the floor is at z = -400
        shifted.append(tmp_path / f"{cam.name}.yaml")
        moved = Camera(cam.name, cam.K, cam.R, cam.t + cam.R @ [0.0, 0.4, 0.0], cam.width, cam.height, cam.dist)
        shifted[-1].write_text(opencv_yaml(moved))
    assert run("rig", "import", *shifted, "--unit", "mm", "--up", "+z", "--silhouettes", tmp_path / "sil",
               "-o", tmp_path / "rig.json") == 0  # fmt: skip
    floor = json.loads((tmp_path / "rig.json").read_text())["floor"]
    assert abs(floor + 400.0) <= 50.0  # the feet touch the floor; the lowest 5 cm layer lies within a layer of it
    same_cameras(load_rig(tmp_path / "rig.json"), RIG, atol=0.05 * 150 / 3)  # up to 5 cm off, 3 m away


@pytest.mark.parametrize("drop, fragment", [("tvec", "missing key for the translation (tvec/T/t/translation)"),
                                            ("camera_matrix", "no camera found")])  # fmt: skip
def test_unreadable_calibrations_are_one_line_naming_file_and_key(tmp_path, capsys, drop, fragment):
    text = opencv_yaml(RIG[0])
    start = text.index(f"{drop}:")
    end = text.index("]", start) + 2
    path = tmp_path / "cam0.yaml"
    path.write_text(text[:start] + text[end:])
    assert run("rig", "import", path, "-o", tmp_path / "rig.json") == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith(f"voxpose: error: {path}") and fragment in err, err
    assert not (tmp_path / "rig.json").exists()
