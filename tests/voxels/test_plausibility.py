"""Plausibility checks: a rig in the wrong unit or with the wrong up axis stops with one line naming the fix;
cameras on less than half a circle warn of ghost volume."""

import json

import numpy as np
import pytest

from tests.helpers import tpose
from voxpose.cli.main import main
from voxpose.errors import VoxposeError
from voxpose.voxels.body import body_ellipsoids
from voxpose.voxels.cameras import circular_rig, rig_json
from voxpose.voxels.plausibility import check_height, check_rig
from voxpose.voxels.render import render_silhouettes
from voxpose.voxels.silhouettes import write_silhouette_folder

RIG = circular_rig(n=4, focal_px=150.0, width=128, image_height=128, name="four")


def test_cameras_whose_images_see_the_world_upside_down():
    check_rig(RIG, "rig.json")
    upside_down = json.loads(rig_json(RIG))
    from voxpose.voxels.cameras import rig_from_dict

    flipped = rig_from_dict(upside_down | {"up": "-y"}, "rig.json")  # the file read as if its Y pointed down
    with pytest.raises(VoxposeError, match="rig.json: the cameras' images show world \\+Y pointing down.*--up"):
        check_rig(flipped, "rig.json")


def test_a_narrow_arc_of_cameras_warns_of_ghost_volume(caplog):
    from voxpose.voxels.cameras import Rig

    with caplog.at_level("WARNING"):
        check_rig(circular_rig(n=8), "wide")
    assert "ghost" not in caplog.text
    arc = Rig("arc", circular_rig(n=8)[:3])  # 0, 45 and 90 degrees
    with caplog.at_level("WARNING"):
        check_rig(arc, "arc.json")
    assert "arc.json: the cameras span 90 deg" in caplog.text


@pytest.mark.parametrize("h_sub, ok", [(0.9, False), (1.0, True), (1.75, True), (2.3, True), (16.4, False)])
def test_subject_height_outside_one_to_two_point_three_metres(h_sub, ok):
    if ok:
        check_height(h_sub, "rig.json")
    else:
        with pytest.raises(VoxposeError, match="outside 1.0-2.3 m.*--unit"):
            check_height(h_sub, "rig.json")


def test_carve_refuses_a_rig_read_in_the_wrong_unit(tmp_path, capsys):
    sil = render_silhouettes(body_ellipsoids(tpose()).frame(0), RIG)
    write_silhouette_folder([sil], RIG, tmp_path / "sil")
    data = json.loads(rig_json(RIG))
    for cam in data["cameras"]:
        cam["t"] = (10.0 * np.array(cam["t"])).tolist()  # decimetres, read as metres
    (tmp_path / "dm.json").write_text(json.dumps(data))
    status = main(["carve", "--rig", str(tmp_path / "dm.json"), "--silhouettes", str(tmp_path / "sil"),
                   "-o", str(tmp_path / "vox.h5")])  # fmt: skip
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert status == 2 and err.startswith(f"voxpose: error: {tmp_path / 'dm.json'}: the subject is 17.")
    assert "--unit" in err
    assert not (tmp_path / "vox.h5").exists()
