"""Body model: segment geometry on hand-made poses of known geometry, equivariance, proportions.

``make_motion`` (also used by the other carving tests) builds a ``MotionData`` by forward kinematics of
chosen canonical local rotations on a fixed T-pose skeleton, so every joint, end and rotation is known.
"""

import numpy as np
import pytest

from tests.helpers import make_motion, tpose, volume, walk_motion
from voxpose.errors import VoxposeError
from voxpose.motion import canon
from voxpose.motion.data import MotionData
from voxpose.motion.rotations import axis_rotation
from voxpose.voxels.body import DEFAULT_PROPORTIONS, SEGMENTS, body_ellipsoids, resolve_proportions
from voxpose.voxels.landmarks import SHOULDER_HALF_WIDTH, anatomical_points


def _ellipsoid_points(el, f, e, n=2000, seed=0):
    """Points on the surface of ellipsoid e of frame f."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return el.centres[f, e] + (d * el.radii[f, e]) @ el.rotations[f, e].T


def test_tpose_axes_and_extent():
    el = body_ellipsoids(tpose())
    assert el.names == SEGMENTS and el.centres.shape == (1, 16, 3) and el.radii.shape == (1, 16, 3)
    # every frame is a rotation; in the T-pose it is the segment's canonical frame
    rot = el.rotations[0]
    assert np.allclose(rot @ np.swapaxes(rot, -1, -2), np.eye(3), atol=1e-12)
    assert np.allclose(np.linalg.det(rot), 1.0)
    upper = SEGMENTS.index("lupperarm")
    assert np.allclose(rot[upper][:, 0], [1, 0, 0]) and np.allclose(rot[upper][:, 1], [0, 0, 1])
    thigh = SEGMENTS.index("rthigh")
    assert np.allclose(rot[thigh][:, 0], [0, -1, 0]) and np.allclose(rot[thigh][:, 1], [1, 0, 0])
    foot = SEGMENTS.index("lfoot")
    assert np.allclose(rot[foot][:, 0], [0, 0, 1])
    # the upper arm spans shoulder - 0.1 L .. elbow + 0.05 L along +X (L = 0.29 m), the shoulder moved from the
    # joint (0.17 m) to the glenohumeral landmark 0.1295 h from the midline, the arm with it
    shoulder_x = SHOULDER_HALF_WIDTH * 1.75
    centre = el.centres[0, upper]
    half = el.radii[0, upper, 0]
    assert np.isclose(centre[0] - half, shoulder_x - 0.1 * 0.29)
    assert np.isclose(centre[0] + half, shoulder_x + 1.05 * 0.29)
    assert np.allclose(el.radii[0, upper, 1:], 1.75 * DEFAULT_PROPORTIONS["lupperarm"]["width"])
    # head sphere: top touching head_top at 1.75 m
    head = SEGMENTS.index("head")
    assert np.allclose(el.radii[0, head], el.radii[0, head, 0])
    assert np.isclose(el.centres[0, head, 1] + el.radii[0, head, 0], 1.75)


def test_long_axis_follows_each_segment_in_a_posed_frame():
    motion = walk_motion(3)
    el = body_ellipsoids(motion)
    points = np.concatenate(anatomical_points(motion.positions, motion.ends, motion.height), axis=1)
    names = canon.JOINTS + canon.ENDS
    pairs = {"lforearm": ("lelbow", "lwrist"), "rshin": ("rknee", "rankle"), "lfoot": ("lankle", "ltoe")}
    for seg, (a, b) in pairs.items():
        e = SEGMENTS.index(seg)
        d = points[:, names.index(b)] - points[:, names.index(a)]
        d /= np.linalg.norm(d, axis=-1, keepdims=True)
        assert np.allclose(el.rotations[:, e, :, 0], d, atol=1e-12)
        # both joints lie on the long axis inside the ellipsoid
        for joint in (a, b):
            rel = points[:, names.index(joint)] - el.centres[:, e]
            local = np.einsum("fji,fj->fi", el.rotations[:, e], rel) / el.radii[:, e]
            assert np.all(np.sum(local**2, axis=-1) < 1.0)
            assert np.allclose(local[:, 1:], 0, atol=1e-9)


def test_cross_section_turns_with_owner_joint():
    # turning the root by 90 degrees about the vertical turns the pelvis' wide axis from X to -Z
    local = np.broadcast_to(np.eye(3), (1, 14, 3, 3)).copy()
    local[0, 0] = axis_rotation("Y", 90)
    el = body_ellipsoids(make_motion(local, np.array([[0.0, 0.98, 0.0]])))
    pelvis = SEGMENTS.index("pelvis")
    assert np.allclose(el.rotations[0, pelvis][:, 1], [0, 0, -1], atol=1e-12)
    # the extent of the pelvis' surface along X is now its depth, along Z its width
    pts = _ellipsoid_points(el, 0, pelvis)
    depth, width = (1.75 * DEFAULT_PROPORTIONS["pelvis"][k] for k in ("depth", "width"))
    assert np.isclose(np.ptp(pts[:, 0]) / 2, depth, rtol=0.02)
    assert np.isclose(np.ptp(pts[:, 2]) / 2, width, rtol=0.02)


def test_rigid_motion_equivariance():
    motion = walk_motion(3)
    turn = axis_rotation("Y", 37.0) @ axis_rotation("X", 11.0)
    shift = np.array([1.5, -0.2, 3.0])
    rotated = MotionData(
        "moved",
        "moved",
        30.0,
        motion.positions @ turn.T + shift,
        turn @ motion.rotations,
        motion.angles,
        motion.ends @ turn.T + shift,
        motion.offsets,
        motion.height,
    )
    a, b = body_ellipsoids(motion), body_ellipsoids(rotated)
    assert np.allclose(b.centres, a.centres @ turn.T + shift, atol=1e-12)
    assert np.allclose(b.rotations, turn @ a.rotations, atol=1e-12)
    assert np.allclose(b.radii, a.radii)


def test_sizes_scale_with_height_and_volume_is_plausible():
    small, tall = body_ellipsoids(tpose(height=1.5)), body_ellipsoids(tpose(height=2.0))
    assert np.allclose(tall.radii * 1.5, small.radii * 2.0)
    # the default body of a 1.75 m subject: a heavy-set adult's volume (documented calibration)
    total = volume(body_ellipsoids(tpose()))
    assert 0.07 < total < 0.11


def test_proportion_overrides_and_errors():
    base = body_ellipsoids(tpose())
    thin = body_ellipsoids(tpose(), {"lthigh": {"width": 0.03}})
    e = SEGMENTS.index("lthigh")
    assert np.isclose(thin.radii[0, e, 1], 1.75 * 0.03)
    others = [i for i in range(len(SEGMENTS)) if i != e]
    assert np.allclose(thin.radii[0, others], base.radii[0, others])
    assert resolve_proportions()["head"] == DEFAULT_PROPORTIONS["head"]
    with pytest.raises(VoxposeError, match="unknown segment 'tail'"):
        resolve_proportions({"tail": {"width": 0.1}})
    with pytest.raises(VoxposeError, match=r"unknown key lthigh\.radius"):
        resolve_proportions({"lthigh": {"radius": 0.1}})
    with pytest.raises(VoxposeError, match=r"chest\.depth must be positive"):
        resolve_proportions({"chest": {"depth": 0.0}})
    with pytest.raises(VoxposeError, match=r"head\.radius must be a number"):
        resolve_proportions({"head": {"radius": "big"}})


def test_bad_pose_input():
    motion = tpose(2)
    arrays = {k: getattr(motion, k) for k in ("positions", "rotations", "ends", "height")}
    with pytest.raises(VoxposeError, match="lack key"):
        body_ellipsoids({"positions": arrays["positions"]})
    broken = dict(arrays, ends=arrays["ends"][:, :3])
    with pytest.raises(VoxposeError, match="ends has shape"):
        body_ellipsoids(broken)
    nan = dict(arrays, positions=arrays["positions"].copy())
    nan["positions"][1, 3, 0] = np.nan
    with pytest.raises(VoxposeError, match="positions not finite in frame 1"):
        body_ellipsoids(nan)
    degenerate = dict(arrays, ends=arrays["ends"].copy())
    degenerate["ends"][1, 1] = arrays["positions"][1, canon.INDEX["lwrist"]]
    with pytest.raises(VoxposeError, match="segment lhand has zero length in frame 1"):
        body_ellipsoids(degenerate)
    # the dict form gives the same solids as the MotionData form
    assert np.allclose(body_ellipsoids(arrays).centres, body_ellipsoids(motion).centres)
