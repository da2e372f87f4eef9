"""BVH reading and writing: round trips, channel bookkeeping, and one error per kind of malformed file."""

import re

import numpy as np
import pytest

import voxpose.io.bvh as bvh_module
from tests.helpers import random_motion
from voxpose.errors import VoxposeError
from voxpose.io.bvh import (
    Bvh,
    BvhJoint,
    channel_slices,
    joint_columns,
    read_bvh,
    read_duration,
    rotation_order,
    write_bvh,
)

SMALL = """HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT Spine {
    OFFSET 0.0 2.5 -0.125
    CHANNELS 3 Yrotation Xrotation Zrotation
    End Site
    {
      OFFSET 0 1 0
    }
  }
  JOINT Leg
  {
    OFFSET 1 -2 0
    CHANNELS 6 Zrotation Xposition Xrotation Yposition Zposition Yrotation
  }
}
MOTION
Frames:\t2
Frame Time: .0083333
1 2 3 10 20 30 40 50 60 70 1.5 80 2.5 3.5 90

-1 -2 -3 -10 -20 -30 -40 -50 -60 -70 -1.5 -80 -2.5 -3.5 -90
"""


def write(tmp_path, text, name="m.bvh"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_parse_small_file(tmp_path):
    b = read_bvh(write(tmp_path, SMALL))
    assert [j.name for j in b.joints] == ["Hips", "Spine", "Leg"]
    assert [j.parent for j in b.joints] == [-1, 0, 0]
    assert np.array_equal(b.joints[1].offset, [0.0, 2.5, -0.125])
    assert np.array_equal(b.joints[1].end_site, [0.0, 1.0, 0.0])
    assert b.joints[0].end_site is None and b.joints[2].end_site is None
    assert b.frame_time == pytest.approx(0.0083333)
    assert b.motion.shape == (2, 15) and b.motion.dtype == np.float64
    assert b.motion[1, 0] == -1 and b.motion[0, 10] == 1.5


def test_read_duration_matches_the_full_parse(tmp_path):
    path = write(tmp_path, SMALL)
    full = read_bvh(path)
    assert read_duration(path) == (full.motion.shape[0], full.frame_time)
    with pytest.raises(VoxposeError, match="no MOTION section"):
        read_duration(write(tmp_path, SMALL.split("MOTION")[0], "cut.bvh"))
    with pytest.raises(VoxposeError, match="Frames: expected a whole number"):
        read_duration(write(tmp_path, SMALL.replace("Frames:\t2", "Frames:\ttwo"), "bad.bvh"))


def test_channel_helpers(tmp_path):
    b = read_bvh(write(tmp_path, SMALL))
    assert channel_slices(b) == [slice(0, 6), slice(6, 9), slice(9, 15)]
    assert [rotation_order(j) for j in b.joints] == ["ZYX", "YXZ", "ZXY"]
    # Leg: Zrotation Xposition Xrotation Yposition Zposition Yrotation at columns 9..14
    pos, rot = joint_columns(b, 2)
    assert pos == [10, 12, 13] and rot == [9, 11, 14]
    assert b.motion[0, pos].tolist() == [1.5, 2.5, 3.5] and b.motion[0, rot].tolist() == [70.0, 80.0, 90.0]
    assert joint_columns(b, 1) == (None, [6, 7, 8])


def test_round_trip_real_values(tmp_path):
    original = random_motion(n_frames=25, seed=3)
    write_bvh(original, tmp_path / "a.bvh", precision=6)
    once = read_bvh(tmp_path / "a.bvh")
    # values equal the printed ones: 6 significant digits
    printed = np.array([[float(f"{v:.6g}") for v in row] for row in original.motion])
    assert np.array_equal(once.motion, printed)
    write_bvh(once, tmp_path / "b.bvh", precision=6)
    twice = read_bvh(tmp_path / "b.bvh")
    assert np.array_equal(twice.motion, once.motion)
    assert (tmp_path / "a.bvh").read_text() == (tmp_path / "b.bvh").read_text()
    for a, b in zip(original.joints, twice.joints, strict=True):
        assert (a.name, a.parent, a.channels) == (b.name, b.parent, b.channels)
        assert np.array_equal(a.offset, b.offset)
        assert (a.end_site is None) == (b.end_site is None)
        if a.end_site is not None:
            assert np.array_equal(a.end_site, b.end_site)
    assert twice.frame_time == pytest.approx(original.frame_time, rel=1e-9)


def test_round_trip_full_precision_is_exact(tmp_path):
    original = random_motion(n_frames=10, seed=4)
    write_bvh(original, tmp_path / "a.bvh", precision=17)
    assert np.array_equal(read_bvh(tmp_path / "a.bvh").motion, original.motion)


def test_round_trip_parsed_file(tmp_path):
    b = read_bvh(write(tmp_path, SMALL))
    write_bvh(b, tmp_path / "out.bvh")
    again = read_bvh(tmp_path / "out.bvh")
    assert np.array_equal(again.motion, b.motion)
    assert [(j.name, j.parent, j.channels) for j in again.joints] == [(j.name, j.parent, j.channels) for j in b.joints]


@pytest.mark.parametrize(
    ("old", "new", "line", "message"),
    [
        ("Frames:\t2", "Frames:\t3", 25, "truncated MOTION: Frames: 3 but 2 frame lines"),
        ("-1 -2 -3 -10", "-1 -2 -10", 25, "frame line has 14 values, expected 15"),
        ("1 2 3 10 20", "1 2 3 1O 20", 23, "frame value '1O' is not a number"),
        ("1 2 3 10 20", "1 2 3 nan 20", 23, "'nan' is not a finite number"),
        ("Frames:\t2\n", "", 21, "expected 'Frames: <value>'"),
        ("Frame Time: .0083333\n", "", 22, "expected 'Frame Time: <value>'"),
        ("Frame Time: .0083333", "Frame Time: 0", 22, "Frame Time must be positive"),
        ("Frames:\t2", "Frames: two", 21, "Frames: expected a whole number, found 'two'"),
        ("Yrotation Xrotation Zrotation", "Yrotation Xrotation Wrotation", 8, "unknown channel 'Wrotation'"),
        ("CHANNELS 3 Yrotation", "CHANNELS 4 Yrotation", 9, "unknown channel 'End' in joint 'Spine'"),
        ("OFFSET 1 -2 0", "OFFSET 1 -2 zero", 16, "OFFSET of 'Leg': 'zero' is not a number"),
        ("    }\n  }\n  JOINT Leg", "    }\n  JOINT Leg", 18, "expected '}' closing joint 'Hips'"),
        ("  }\n}\nMOTION", "  }\n}\n}\nMOTION", 20, "unexpected '}' after the root joint"),
        ("JOINT Spine {", "JOINT Spine { garbage", 6, "unexpected 'garbage' in joint 'Spine'"),
        ("HIERARCHY", "HIERARCH", 1, "expected 'HIERARCHY'"),
        ("    OFFSET 0.0 2.5 -0.125\n", "", 6, "joint 'Spine' has no OFFSET"),
    ],
)
def test_malformed_files(tmp_path, old, new, line, message):
    assert old in SMALL
    path = write(tmp_path, SMALL.replace(old, new, 1))
    with pytest.raises(VoxposeError) as err:
        read_bvh(path)
    text = str(err.value)
    assert text.startswith(f"{path}:{line}: "), text
    assert message in text, text
    assert "\n" not in text


def test_missing_motion_and_extra_lines(tmp_path):
    with pytest.raises(VoxposeError, match=r":\d+: no MOTION section"):
        read_bvh(write(tmp_path, SMALL.split("MOTION")[0]))
    with pytest.raises(VoxposeError, match=r"m.bvh:26: more frame lines than Frames: 2"):
        read_bvh(write(tmp_path, SMALL + "1 " * 15 + "\n"))
    with pytest.raises(VoxposeError, match="cannot read BVH file"):
        read_bvh(tmp_path / "absent.bvh")


def test_channel_count_must_be_three_of_a_kind(tmp_path):
    text = SMALL.replace("CHANNELS 3 Yrotation Xrotation Zrotation", "CHANNELS 2 Yrotation Xrotation")
    with pytest.raises(VoxposeError, match=re.escape("m.bvh:8: joint 'Spine' must have all three or none")):
        read_bvh(write(tmp_path, text))


def _assert_dir_unchanged(folder, before):
    assert sorted(p.name for p in folder.iterdir()) == before


def test_write_failure_leaves_nothing(tmp_path, monkeypatch):
    good = random_motion(n_frames=5, seed=1)
    (tmp_path / "keep.bvh").write_text("old")
    before = sorted(p.name for p in tmp_path.iterdir())

    bad = Bvh(joints=good.joints, frame_time=good.frame_time, motion=good.motion[:, :-1])
    with pytest.raises(VoxposeError, match="motion has shape"):
        write_bvh(bad, tmp_path / "new.bvh")
    _assert_dir_unchanged(tmp_path, before)

    nan = Bvh(joints=good.joints, frame_time=good.frame_time, motion=good.motion.copy())
    nan.motion[2, 3] = np.nan
    with pytest.raises(VoxposeError, match="NaN"):
        write_bvh(nan, tmp_path / "keep.bvh")
    _assert_dir_unchanged(tmp_path, before)
    assert (tmp_path / "keep.bvh").read_text() == "old"

    def fail(*args):
        raise OSError("disk full")

    monkeypatch.setattr(bvh_module, "_format_rows", fail)  # fails after the hierarchy is written
    with pytest.raises(OSError):
        write_bvh(good, tmp_path / "keep.bvh")
    _assert_dir_unchanged(tmp_path, before)
    assert (tmp_path / "keep.bvh").read_text() == "old"


def test_write_rejects_unwritable_hierarchies(tmp_path):
    j = [
        BvhJoint("A", -1, np.zeros(3), ("Xrotation", "Yrotation", "Zrotation")),
        BvhJoint("B", 0, np.ones(3), ("Xrotation", "Yrotation", "Zrotation")),
        BvhJoint("C", 1, np.ones(3), ("Xrotation", "Yrotation", "Zrotation")),
        BvhJoint("D", 0, np.ones(3), ("Xrotation", "Yrotation", "Zrotation")),
    ]
    motion = np.zeros((1, 12))
    interleaved = [j[0], j[1], j[3], j[2]]
    interleaved[3] = BvhJoint("C", 1, np.ones(3), j[2].channels)
    with pytest.raises(VoxposeError, match="depth-first"):
        write_bvh(Bvh(interleaved, 0.1, motion), tmp_path / "x.bvh")
    with pytest.raises(VoxposeError, match="bad channels"):
        write_bvh(Bvh([BvhJoint("A", -1, np.zeros(3), ("Wrotation",))], 0.1, np.zeros((1, 1))), tmp_path / "x.bvh")
    with pytest.raises(VoxposeError, match="precision"):
        write_bvh(Bvh(j, 0.1, motion), tmp_path / "x.bvh", precision=0)
    assert list(tmp_path.iterdir()) == []
