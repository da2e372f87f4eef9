"""The generated subject's skeleton: names, channels, Winter's proportions and its standing height."""

import numpy as np
import pytest

from tests.helpers import rest_points, standing_height_from_bones
from voxpose.errors import VoxposeError
from voxpose.motion.generated_skeleton import JOINT_NAMES, default_skeleton

EXPECTED_NAMES = (
    "Hips Spine Chest Neck Head LeftShoulder LeftArm LeftForeArm LeftHand RightShoulder RightArm "
    "RightForeArm RightHand LeftUpLeg LeftLeg LeftFoot LeftToe RightUpLeg RightLeg RightFoot RightToe"
).split()
J = {name: i for i, name in enumerate(JOINT_NAMES)}


@pytest.mark.parametrize("height", [1.5, 1.75, 2.0])
def test_skeleton_names_channels_and_standing_height(height):
    joints = default_skeleton(height)
    assert [j.name for j in joints] == EXPECTED_NAMES
    assert joints[0].parent == -1 and len(joints[0].channels) == 6
    assert all(j.channels == ("Zrotation", "Xrotation", "Yrotation") for j in joints[1:])
    assert all(0 <= j.parent < i for i, j in enumerate(joints) if i)
    assert {j.name for j in joints if j.end_site is not None} == {
        "Head",
        "LeftHand",
        "RightHand",
        "LeftToe",
        "RightToe",
    }
    assert standing_height_from_bones(joints) == pytest.approx(height, abs=1e-12)
    pos, ends = rest_points(joints)
    # Winter's proportions: hip joint 0.530 H above the toes' ground line, shoulder 0.818 H, mirror symmetry
    assert pos[J["LeftUpLeg"], 1] - ends["LeftToe"][1] == pytest.approx(0.530 * height)
    assert pos[J["LeftArm"], 1] - ends["LeftToe"][1] == pytest.approx(0.818 * height)
    assert pos[J["LeftArm"], 0] - pos[J["RightArm"], 0] == pytest.approx(0.259 * height)
    for name in EXPECTED_NAMES:
        if name.startswith("Left"):
            np.testing.assert_allclose(pos[J[name]] * [-1, 1, 1], pos[J[name.replace("Left", "Right")]])
    assert ends["LeftHand"][0] > pos[J["LeftArm"], 0] > 0  # T-pose: left arm along +X


@pytest.mark.parametrize("height", [float("nan"), 0.3, True, "1.8"])
def test_bad_heights_are_voxpose_errors(height):
    with pytest.raises(VoxposeError, match="height"):
        default_skeleton(height)
