"""Eq. 6 and its aggregates against values computed by hand."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.evaluation.metrics import (
    angle_differences,
    frame_errors,
    full_body_error,
    heading_by_bin,
    heading_error,
    joint_error,
    per_angle_error,
    per_joint_error,
    position_errors_mm,
    table_errors,
)
from voxpose.motion import canon


def pair(true_value, est_value, column=0, frames=1):
    a = np.zeros((frames, 42))
    b = np.zeros((frames, 42))
    a[:, column] = true_value
    b[:, column] = est_value
    return a, b


@pytest.mark.parametrize(
    "true_value, est_value, expected",
    [
        (350, 10, 20),  # across the 0/360 seam
        (710, 10, 20),  # unwrapped angles compare modulo 360
        (10, 710, 20),
        (-170, 170, 20),
        (0, 180, 180),
        (30, 30 + 720, 0),
        (45, -45, 90),
    ],
)
def test_wrapped_difference(true_value, est_value, expected):
    a, b = pair(true_value, est_value)
    assert angle_differences(a, b)[0, 0] == pytest.approx(expected)
    assert frame_errors(a, b)[0] == pytest.approx(expected / 42)


def test_time_aggregates_rms_and_mean():
    # angle 5 is off by 3 and 4 degrees in two frames: RMS sqrt(12.5), mean 3.5
    a = np.zeros((2, 42))
    b = np.zeros((2, 42))
    b[:, 5] = [3, -4]
    assert per_angle_error(a, b)[5] == pytest.approx(np.sqrt(12.5))
    assert per_angle_error(a, b, "mean")[5] == pytest.approx(3.5)
    assert full_body_error(a, b) == pytest.approx(np.sqrt(12.5) / 42)
    # mean over time of Eq. 6 equals the mean aggregate
    assert full_body_error(a, b, "mean") == pytest.approx(frame_errors(a, b).mean())
    # angle 5 is the third angle of joint 1 (the neck): its joint error is a third of the angle's
    joint = canon.JOINTS[5 // 3]
    assert joint_error(a, b, joint) == pytest.approx(np.sqrt(12.5) / 3)
    assert per_joint_error(a, b)[5 // 3] == pytest.approx(np.sqrt(12.5) / 3)
    assert np.count_nonzero(per_joint_error(a, b)) == 1


def test_heading_and_named_joints():
    a = np.zeros((3, 42))
    b = np.zeros((3, 42))
    b[:, 0] = [350, 10, 0]  # root's first angle: 10, 10, 0 degrees off
    ls = 3 * canon.INDEX["lshoulder"]
    b[:, ls : ls + 3] = [[6, 0, 0], [0, 6, 0], [0, 0, 6]]
    assert heading_error(a, b) == pytest.approx(np.sqrt(200 / 3))
    assert heading_error(a, b, "mean") == pytest.approx(20 / 3)
    assert joint_error(a, b, "lshoulder") == pytest.approx(np.sqrt(12))  # each angle: RMS sqrt(36/3)
    assert joint_error(a, b, "rhip") == 0
    table = table_errors(a, b)
    assert table["heading"] == pytest.approx(np.sqrt(200 / 3))
    assert table["lshoulder_mean"] == pytest.approx(2.0)
    assert set(table) == {
        "full_body",
        "heading",
        "lshoulder",
        "rhip",
        "full_body_mean",
        "heading_mean",
        "lshoulder_mean",
        "rhip_mean",
    }


def test_heading_by_bin_counts_frames_errors_and_flips_per_true_heading():
    a = np.zeros((5, 42))
    b = np.zeros((5, 42))
    a[:, 0] = [10, 20, -10, 359, 95]  # bins 0, 0, 11, 11, 3 of 30 degrees
    b[:, 0] = [10, 60, 170, 0, 95 + 140]  # errors 0, 40, 180 (a flip), 1, 140 (a flip)
    rows = heading_by_bin(a, b)
    assert [(r["from"], r["frames"]) for r in rows] == [(0, 2), (90, 1), (330, 2)]
    assert [r["rms"] for r in rows] == pytest.approx([np.sqrt(1600 / 2), 140, np.sqrt((180**2 + 1) / 2)])
    assert [r["flips"] for r in rows] == [0.0, 1.0, 0.5]


def test_position_error_of_a_heading_error():
    # only the neck is offset (0.3 m along X): the neck and the 6 arm joints below it sit there, the 6 leg
    # joints at the root. A 180-degree heading error moves the 7 upper joints by 0.6 m, the legs not at all;
    # the mean runs over the 13 joints other than the root.
    offsets = np.zeros((14, 3))
    offsets[canon.INDEX["neck"]] = [0.3, 0.0, 0.0]
    a = np.zeros((2, 42))
    b = np.zeros((2, 42))
    b[1, 0] = 180.0
    err = position_errors_mm(a, b, offsets)
    assert err == pytest.approx([0.0, 7 * 600.0 / 13])
    assert table_errors(a, b, offsets)["position_mm"] == pytest.approx(7 * 300.0 / 13)


@pytest.mark.parametrize(
    "a, b, message",
    [
        (np.zeros((2, 42)), np.zeros((3, 42)), "differ in shape"),
        (np.zeros((2, 42)), np.full((2, 42), np.nan), "NaN"),
        (np.zeros(42), np.zeros(42), "2-D"),
    ],
)
def test_bad_input_raises(a, b, message):
    with pytest.raises(VoxposeError, match=message):
        frame_errors(a, b)


def test_bad_names_raise():
    a = np.zeros((2, 42))
    with pytest.raises(VoxposeError, match="unknown joint"):
        joint_error(a, a, "lfinger")
    with pytest.raises(VoxposeError, match="over_time"):
        per_angle_error(a, a, "median")
    with pytest.raises(VoxposeError, match="42 columns"):
        per_joint_error(np.zeros((2, 8)), np.zeros((2, 8)))
