"""Does the estimated pose hold when the world turns about the vertical? (issue 18, item 4)

Turning the whole world about the vertical, the cameras and the subject together, changes nothing a camera
sees: only the coordinates, hence the voxel grid and the world-aligned descriptors (Section 4), turn with it.
A pose estimator that holds changes the body heading by the turn and leaves the other angles alone: the
root's Euler order is Y-X-Z (``voxpose.motion.canon``), so ``Ry(phi) Ry(a0) Rx(a1) Rz(a2)`` has heading
``a0 + phi`` and the same ``a1``, ``a2`` and joint angles. ``rotation_response`` measures both on a motion:
per turn, the predicted heading change minus the turn and the RMS change of the 39 angles below the root.
Turns by multiples of 90 degrees map the voxel grid onto itself, so the carved hull turns exactly; other
turns carve it on a grid turned against the body, a change of the same kind as moving the world by a
fraction of a voxel, which ``shift_response`` measures.
"""

from dataclasses import replace

import numpy as np

from voxpose.apply.predict import describe, featurise, regress
from voxpose.evaluation.metrics import angle_differences
from voxpose.features.heading_sense import wrapped
from voxpose.motion import canon
from voxpose.motion.data import MotionData
from voxpose.motion.rotations import axis_rotation
from voxpose.voxels.cameras import Rig
from voxpose.voxels.voxelize import voxelize_motion

HEADING = canon.ANGLE_NAMES.index("root_y")
BODY = [i for i, name in enumerate(canon.ANGLE_NAMES) if not name.startswith("root_")]  # the 39 angles


def turned_rig(rig: Rig, degrees: float) -> Rig:
    """The rig with every camera turned by ``degrees`` about the vertical through the origin (a camera's
    centre ``-R^T t`` turns with it: ``R' = R Ry^T``, ``t`` unchanged)."""
    yaw = axis_rotation("Y", float(degrees))
    return Rig(rig.name, [replace(cam, R=cam.R @ yaw.T) for cam in rig.cameras])


def shifted_rig(rig: Rig, offset) -> Rig:
    """The rig with every camera moved by ``offset`` (3,) metres (``t' = t - R offset``): the subject, placed above
    the rig's centre, moves with it against the voxel grid; a sub-voxel shift measures the carving's own noise."""
    offset = np.asarray(offset, dtype=float)
    return Rig(rig.name, [replace(cam, t=cam.t - cam.R @ offset) for cam in rig.cameras])


def turned_motion(motion: MotionData, degrees: float) -> MotionData:
    """The motion turned by ``degrees`` about the vertical through the origin: joint and end positions and
    world rotations turned, the heading angle increased by ``degrees``, every other angle unchanged."""
    yaw = axis_rotation("Y", float(degrees))
    angles = motion.angles.copy()
    angles[:, HEADING] += float(degrees)
    return replace(motion, positions=motion.positions @ yaw.T, rotations=yaw @ motion.rotations,
                   angles=angles, ends=motion.ends @ yaw.T)  # fmt: skip


def predict_motion(model, motion: MotionData, rig: Rig, proportions=None) -> np.ndarray:
    """(F, 42) angles a model estimates for a motion rendered into ``rig`` and carved with the model's
    voxel settings (``voxpose.apply.predict``, without the root fit), NaN rows at gaps."""
    v = model.voxels
    seq = voxelize_motion(motion, rig, proportions=proportions, l_res_fraction=v["l_res_fraction"],
                          min_views=v["min_views"], n_basis=v["n_basis"], seed=v["seed"],
                          progress_every=0)  # fmt: skip
    described = featurise(model, *describe(model, seq))
    return regress(model, described.features, described.counts > 0, described.heading_offsets())


def response(base: np.ndarray, turned: np.ndarray, degrees: float) -> dict:
    """How predictions ``turned`` (F, 42) of the world turned by ``degrees`` differ from ``base``: the heading
    change minus the turn (mean, RMS and max |.| over frames, wrapped) and the RMS over frames and the 39
    angles below the root of their wrapped change (the root's tilt ``root_x``, ``root_z`` separately)."""
    ok = np.isfinite(base).all(axis=1) & np.isfinite(turned).all(axis=1)
    off = wrapped(turned[ok, HEADING] - base[ok, HEADING] - degrees)
    change = angle_differences(base[ok], turned[ok])
    tilt = [canon.ANGLE_NAMES.index(n) for n in ("root_x", "root_z")]
    return {"degrees": float(degrees), "frames": int(ok.sum()), "heading_mean": float(off.mean()),
            "heading_rms": float(np.sqrt(np.mean(off**2))), "heading_max": float(np.abs(off).max()),
            "body_rms": float(np.sqrt(np.mean(change[:, BODY] ** 2))),
            "tilt_rms": float(np.sqrt(np.mean(change[:, tilt] ** 2)))}  # fmt: skip


def shift_response(model, motion: MotionData, rig: Rig, offset, proportions=None) -> dict:
    """``response`` (with no turn) of the world moved by ``offset`` metres against the voxel grid: what the
    carving's discretisation alone does to the estimates, the floor a turn off the grid's axes cannot beat."""
    base = predict_motion(model, motion, rig, proportions)
    return response(base, predict_motion(model, motion, shifted_rig(rig, offset), proportions), 0.0)


def rotation_response(model, motion: MotionData, rig: Rig, degrees, proportions=None) -> list[dict]:
    """``response`` of the world turned by each of ``degrees`` (cameras and subject together) against the
    unturned world, with each one's heading error against the truth (RMS, degrees) as ``heading_error``."""
    base = predict_motion(model, motion, rig, proportions)
    rows = []
    for d in degrees:
        world = turned_motion(motion, d)
        pred = base if d == 0 else predict_motion(model, world, turned_rig(rig, d), proportions)
        ok = np.isfinite(pred).all(axis=1)
        error = angle_differences(world.angles[ok][:, [HEADING]], pred[ok][:, [HEADING]])
        rows.append(response(base, pred, d) | {"heading_error": float(np.sqrt(np.mean(error**2)))})
    return rows
