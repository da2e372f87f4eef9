"""Test helpers with known geometry, shared by the test modules (imported as ``tests.helpers``).

Hand-made BVH skeletons (``tpose_bvh``, ``random_motion``) and edits of them (``rescaled``, ``renamed``, ...),
canonical motions built by forward kinematics of chosen local rotations (``make_motion``, ``walk_motion``) and
exact visual hulls of known solids (``exact_hull``).
"""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

from voxpose.io.bvh import POSITION_CHANNELS, Bvh, BvhJoint, joint_columns, rotation_order
from voxpose.motion import canon
from voxpose.motion.bvh_kinematics import local_transforms
from voxpose.motion.data import MotionData
from voxpose.motion.rotations import axis_rotation, matrix_to_euler
from voxpose.voxels.body import Ellipsoids
from voxpose.voxels.sequence import VoxelSequence

ROOT = Path(__file__).resolve().parents[1]

SHARED_BVH = Path(__file__).resolve().parents[1].parent / "shared/data/bvh"
SHARED_LIBRARY = SHARED_BVH.with_name("bvh-library")  # gestures, fights, ..., and the ReActIdle family


ROOT_CHANNELS = ("Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation")


JOINT_CHANNELS = ("Zrotation", "Xrotation", "Yrotation")


# A T-pose skeleton in metres (Y up, facing +Z, the subject's left at +X) with the generated preset's
# names: (name, parent name, offset, End Site offset or None). The toes are level with the ankles.
_GENERATED = [
    ("Hips", None, (0.0, 0.0, 0.0), None),
    ("Spine", "Hips", (0.0, 0.10, 0.0), None),
    ("Chest", "Spine", (0.0, 0.15, 0.0), None),
    ("Neck", "Chest", (0.0, 0.25, 0.0), None),
    ("Head", "Neck", (0.0, 0.08, 0.0), (0.0, 0.17, 0.0)),
    ("LeftShoulder", "Chest", (0.03, 0.22, 0.0), None),
    ("LeftArm", "LeftShoulder", (0.15, 0.0, 0.0), None),
    ("LeftForeArm", "LeftArm", (0.28, 0.0, 0.0), None),
    ("LeftHand", "LeftForeArm", (0.25, 0.0, 0.0), (0.09, 0.0, 0.0)),
    ("RightShoulder", "Chest", (-0.03, 0.22, 0.0), None),
    ("RightArm", "RightShoulder", (-0.15, 0.0, 0.0), None),
    ("RightForeArm", "RightArm", (-0.28, 0.0, 0.0), None),
    ("RightHand", "RightForeArm", (-0.25, 0.0, 0.0), (-0.09, 0.0, 0.0)),
    ("LeftUpLeg", "Hips", (0.09, -0.08, 0.0), None),
    ("LeftLeg", "LeftUpLeg", (0.0, -0.42, 0.0), None),
    ("LeftFoot", "LeftLeg", (0.0, -0.41, 0.0), None),
    ("LeftToe", "LeftFoot", (0.0, 0.0, 0.12), (0.0, 0.0, 0.05)),
    ("RightUpLeg", "Hips", (-0.09, -0.08, 0.0), None),
    ("RightLeg", "RightUpLeg", (0.0, -0.42, 0.0), None),
    ("RightFoot", "RightLeg", (0.0, -0.41, 0.0), None),
    ("RightToe", "RightFoot", (0.0, 0.0, 0.12), (0.0, 0.0, 0.05)),
]


# The same body with CMU cgspeed names: a finger joint carries the hand's End Site, ToeBase the toe's.
_CMU_NAMES = {"LeftToe": "LeftToeBase", "RightToe": "RightToeBase"}


def _cmu_layout():
    out = []
    for name, parent, offset, site in _GENERATED:
        name, parent = _CMU_NAMES.get(name, name), _CMU_NAMES.get(parent, parent)
        if name in ("LeftHand", "RightHand"):
            side = name[:-4]
            sign = 1.0 if side == "Left" else -1.0
            out.append((name, parent, offset, None))
            out.append((f"{side}HandIndex1", name, (sign * 0.05, 0.0, 0.0), (sign * 0.04, 0.0, 0.0)))
        else:
            out.append((name, parent, offset, site))
    return out


def _depth_first(layout):
    """Order a (name, parent, ...) list depth first, children in listed order."""
    children = {}
    for row in layout:
        children.setdefault(row[1], []).append(row)
    out, stack = [], list(reversed(children[None]))
    while stack:
        row = stack.pop()
        out.append(row)
        stack.extend(reversed(children.get(row[0], [])))
    return out


def skeleton(style: str = "generated") -> list[BvhJoint]:
    """The hand-made T-pose skeleton, ``style`` "generated" or "cmu" (names of that preset)."""
    layout = _depth_first(_GENERATED if style == "generated" else _cmu_layout())
    index = {row[0]: i for i, row in enumerate(layout)}
    return [
        BvhJoint(
            name=name,
            parent=-1 if parent is None else index[parent],
            offset=np.array(offset, dtype=float),
            channels=ROOT_CHANNELS if parent is None else JOINT_CHANNELS,
            end_site=None if site is None else np.array(site, dtype=float),
        )
        for name, parent, offset, site in layout
    ]


def tpose_bvh(style: str = "generated", n_frames: int = 1, root=(0.0, 0.95, 0.0)) -> Bvh:
    """The skeleton standing still in its T-pose at ``root`` for ``n_frames`` frames (30 fps)."""
    joints = skeleton(style)
    motion = np.zeros((n_frames, sum(len(j.channels) for j in joints)))
    motion[:, :3] = root
    return Bvh(joints=joints, frame_time=1 / 30, motion=motion)


def set_rotation(bvh: Bvh, name: str, zxy) -> None:
    """Set joint ``name``'s rotation channels (Z, X, Y order of ``JOINT_CHANNELS``) in every frame."""
    j = next(i for i, joint in enumerate(bvh.joints) if joint.name == name)
    _, rot = joint_columns(bvh, j)
    bvh.motion[:, rot] = zxy


def random_motion(
    style: str = "generated", n_frames: int = 40, seed: int = 0, rigid_trunk: bool = False, fps: float = 30.0
) -> Bvh:
    """Smooth random motion of the hand-made skeleton at ``fps``: each rotation channel a seeded sum of sinusoids.

    ``rigid_trunk`` keeps the spine, neck, head and clavicles still, so the pelvis and neck frames are
    rigidly attached to each other (canonical forward kinematics is then exact).
    """
    rng = np.random.default_rng(seed)
    bvh = tpose_bvh(style, n_frames)
    bvh.frame_time = 1.0 / fps
    t = np.arange(n_frames) / fps
    amplitude = rng.uniform(10.0, 40.0, size=(3, bvh.motion.shape[1]))
    freq = rng.uniform(0.3, 1.5, size=(3, bvh.motion.shape[1]))
    phase = rng.uniform(0, 2 * np.pi, size=(3, bvh.motion.shape[1]))
    values = np.sum(amplitude[:, None] * np.sin(2 * np.pi * freq[:, None] * t[None, :, None] + phase[:, None]), 0)
    trunk = {"Spine", "Chest", "Neck", "Head", "LeftShoulder", "RightShoulder"}
    for j, joint in enumerate(bvh.joints):
        pos, rot = joint_columns(bvh, j)
        if rot is not None and not (rigid_trunk and joint.name in trunk):
            bvh.motion[:, rot] = values[:, rot] / 2.0
    bvh.motion[:, 0] = 0.3 + 1.2 * t
    bvh.motion[:, 1] = 0.95 + 0.03 * np.sin(4 * np.pi * t)
    bvh.motion[:, 2] = -0.2 + 0.1 * t
    return bvh


def rebase_frames(bvh: Bvh, frames: dict) -> Bvh:
    """The same motion with joint frames turned by constant rotations ``C_j`` (``{name: 3x3}``).

    New offsets and translation channels ``C_p^T t``, local rotations ``C_p^T L_j C_j``, End Sites
    ``C_j^T e``: world positions are unchanged and world rotations become ``W_j C_j``.
    """
    turn = [np.asarray(frames.get(j.name, np.eye(3))) for j in bvh.joints]
    translations, local = local_transforms(bvh)
    motion = bvh.motion.copy()
    joints = []
    for j, joint in enumerate(bvh.joints):
        parent_turn = turn[joint.parent] if joint.parent >= 0 else np.eye(3)
        pos, rot = joint_columns(bvh, j)
        motion[:, rot] = matrix_to_euler(parent_turn.T @ local[:, j] @ turn[j], rotation_order(joint))
        if pos is not None:
            motion[:, pos] = translations[:, j] @ parent_turn
        site = None if joint.end_site is None else turn[j].T @ joint.end_site
        joints.append(BvhJoint(joint.name, joint.parent, parent_turn.T @ joint.offset, joint.channels, site))
    return Bvh(joints=joints, frame_time=bvh.frame_time, motion=motion)


def reorder_channels(bvh: Bvh, seed: int) -> Bvh:
    """The same motion with every joint's channels in a new order (root's order unlike the others')."""
    rng = np.random.default_rng(seed)
    _, local = local_transforms(bvh)
    orders = ["XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"]
    joints, blocks = [], []
    for j, joint in enumerate(bvh.joints):
        pos, _ = joint_columns(bvh, j)
        order = "YZX" if j == 0 else orders[rng.integers(6)]
        values = {f"{a}rotation": v for a, v in zip(order, matrix_to_euler(local[:, j], order).T, strict=True)}
        names = [f"{a}rotation" for a in order]
        if pos is not None:
            values |= {c: bvh.motion[:, col] for c, col in zip(POSITION_CHANNELS, pos, strict=True)}
            moved = [POSITION_CHANNELS[i] for i in rng.permutation(3)]
            names = names + moved if rng.random() < 0.5 else moved + names
        blocks.append(np.stack([values[c] for c in names], axis=1))
        joints.append(BvhJoint(joint.name, joint.parent, joint.offset, tuple(names), joint.end_site))
    return Bvh(joints, bvh.frame_time, np.concatenate(blocks, axis=1))


def rescaled(bvh: Bvh, factor: float) -> Bvh:
    """The same motion in a length unit ``factor`` times smaller: offsets, End Sites and position channels
    multiplied by ``factor`` (rotations unchanged)."""
    motion = bvh.motion.copy()
    joints = []
    for j, joint in enumerate(bvh.joints):
        pos, _ = joint_columns(bvh, j)
        if pos is not None:
            motion[:, pos] *= factor
        site = None if joint.end_site is None else joint.end_site * factor
        joints.append(BvhJoint(joint.name, joint.parent, joint.offset * factor, joint.channels, site))
    return Bvh(joints=joints, frame_time=bvh.frame_time, motion=motion)


def rest_points(joints):
    """Rest-pose positions of joints and End Sites by summing OFFSETs down the tree (independent FK)."""
    pos = np.zeros((len(joints), 3))
    ends = {}
    for i, joint in enumerate(joints):
        pos[i] = joint.offset + (pos[joint.parent] if joint.parent >= 0 else 0.0)
        if joint.end_site is not None:
            ends[joint.name] = pos[i] + joint.end_site
    return pos, ends


def standing_height_from_bones(joints) -> float:
    """Head top above the lowest of the toes and joints in the rest pose (metres)."""
    pos, ends = rest_points(joints)
    return ends["Head"][1] - min(ends["LeftToe"][1], ends["RightToe"][1], pos[:, 1].min())


def renamed(bvh: Bvh, names: dict, drop_sites=()) -> Bvh:
    """``bvh`` with joints renamed by ``names`` (old -> new) and the End Sites of ``drop_sites`` removed."""
    joints = [
        BvhJoint(
            names.get(j.name, j.name),
            j.parent,
            j.offset,
            j.channels,
            None if j.name in drop_sites else j.end_site,
        )
        for j in bvh.joints
    ]
    return Bvh(joints, bvh.frame_time, bvh.motion)


# A fourth skeleton family made from a CMU file (``lab_family``): every joint renamed in a lab's own style,
# unknown to the built-in presets, so it loads only with this joint map (the CMU preset's points, renamed).
LAB_NAMES = {
    "Hips": "hip", "LHipJoint": "lPelvis", "LeftUpLeg": "lThigh", "LeftLeg": "lShin", "LeftFoot": "lFoot",
    "LeftToeBase": "lToe", "LowerBack": "abdomen", "Spine": "abdomen2", "Spine1": "chest", "Neck": "neck",
    "Neck1": "neck2", "Head": "head", "LeftShoulder": "lCollar", "LeftArm": "lShldr", "LeftForeArm": "lForeArm",
    "LeftHand": "lHand", "LeftFingerBase": "lPalm", "LeftHandIndex1": "lIndex1", "LThumb": "lThumb1",
}  # fmt: skip
LAB_NAMES |= {k.replace("Left", "Right").replace("LHip", "RHip").replace("LThumb", "RThumb"): "r" + v[1:]
              for k, v in LAB_NAMES.items() if v[0] == "l"}  # fmt: skip
LAB_JOINT_MAP = {
    "root": "hip", "neck": "neck", "head_top": "head", "lshoulder": "lShldr", "lelbow": "lForeArm",
    "lwrist": "lHand", "lhand_tip": "lIndex1", "lhip": "lThigh", "lknee": "lShin", "lankle": "lFoot", "ltoe": "lToe",
}  # fmt: skip
LAB_JOINT_MAP |= {"r" + k[1:]: "r" + v[1:] for k, v in LAB_JOINT_MAP.items() if k[0] == "l"}


def lab_family(cmu: Bvh, seed: int = 0) -> Bvh:
    """A CMU motion as another family would write it: joints renamed (``LAB_NAMES``) and every joint's
    rotation channels in a new Euler order (``reorder_channels``); the same motion, so the same 42 angles."""
    return renamed(reorder_channels(cmu, seed), LAB_NAMES)


# T-pose offsets of a 1.75 m subject, each in its parent's canonical frame (metres)
OFFSETS = {
    "root": (0.0, 0.0, 0.0),
    "neck": (0.0, 0.52, 0.0),
    "lshoulder": (0.17, -0.05, 0.0),
    "lelbow": (0.29, 0.0, 0.0),
    "lwrist": (0.25, 0.0, 0.0),
    "rshoulder": (-0.17, -0.05, 0.0),
    "relbow": (-0.29, 0.0, 0.0),
    "rwrist": (-0.25, 0.0, 0.0),
    "lhip": (0.09, -0.07, 0.0),
    "lknee": (0.0, -0.44, 0.0),
    "lankle": (0.0, -0.40, 0.0),
    "rhip": (-0.09, -0.07, 0.0),
    "rknee": (0.0, -0.44, 0.0),
    "rankle": (0.0, -0.40, 0.0),
}


END_OFFSETS = {  # end: (joint, offset in the joint's frame)
    "head_top": ("neck", (0.0, 0.25, 0.0)),
    "lhand_tip": ("lwrist", (0.18, 0.0, 0.0)),
    "rhand_tip": ("rwrist", (-0.18, 0.0, 0.0)),
    "ltoe": ("lankle", (0.0, 0.0, 0.16)),
    "rtoe": ("rankle", (0.0, 0.0, 0.16)),
}


ROOT_HEIGHT = 0.98  # root above the floor in the T-pose; the head top is then at 1.75 m


def make_motion(local, root_positions, height=1.75, name="test_motion") -> MotionData:
    """A motion from canonical local rotations (F, 14, 3, 3) and root positions (F, 3), of ``height``."""
    local = np.asarray(local, dtype=float)
    n = local.shape[0]
    scale = height / 1.75
    rot = np.zeros((n, 14, 3, 3))
    pos = np.zeros((n, 14, 3))
    for j, joint in enumerate(canon.JOINTS):
        p = canon.PARENTS[j]
        if p < 0:
            rot[:, j] = local[:, j]
            pos[:, j] = root_positions
        else:
            rot[:, j] = rot[:, p] @ local[:, j]
            pos[:, j] = pos[:, p] + rot[:, p] @ (scale * np.array(OFFSETS[joint]))
    ends = np.stack(
        [pos[:, canon.INDEX[j]] + rot[:, canon.INDEX[j]] @ (scale * np.array(o)) for j, o in END_OFFSETS.values()],
        axis=1,
    )
    offsets = scale * np.array([OFFSETS[j] for j in canon.JOINTS])
    return MotionData(name, name.split("_")[0], 30.0, pos, rot, np.zeros((n, 42)), ends, offsets, height)


def tpose(n_frames=1, height=1.75, root_xz=(0.0, 0.0)) -> MotionData:
    """The T-pose standing on the floor with the root above ``root_xz``."""
    local = np.broadcast_to(np.eye(3), (n_frames, 14, 3, 3)).copy()
    root = np.tile([root_xz[0], ROOT_HEIGHT * height / 1.75, root_xz[1]], (n_frames, 1))
    return make_motion(local, root, height)


def walk_pose_local(phase: float) -> np.ndarray:
    """(14, 3, 3) local rotations of a walking-like pose: arms down and swinging, legs apart, knee bent."""
    local = np.broadcast_to(np.eye(3), (14, 3, 3)).copy()
    index = canon.INDEX
    swing = 30.0 * np.sin(phase)
    local[index["lshoulder"]] = axis_rotation("Z", -75) @ axis_rotation("Y", swing)
    local[index["rshoulder"]] = axis_rotation("Z", 75) @ axis_rotation("Y", swing)
    local[index["lelbow"]] = axis_rotation("Y", -20)
    local[index["relbow"]] = axis_rotation("Y", 20)
    local[index["lhip"]] = axis_rotation("X", -25 * np.sin(phase))
    local[index["rhip"]] = axis_rotation("X", 25 * np.sin(phase))
    local[index["lknee"]] = axis_rotation("X", 30)
    local[index["root"]] = axis_rotation("Y", 20 + 40 * phase)
    return local


def walk_motion(n_frames=4, height=1.75, step=(0.3, 0.0, 0.2)) -> MotionData:
    """A few walking-like poses, the root moving by ``step`` metres per frame."""
    phases = np.linspace(0.0, 2.0, n_frames)
    local = np.stack([walk_pose_local(p) for p in phases])
    root = np.array([[0.0, 0.96 * height / 1.75, 0.0]]) + np.arange(n_frames)[:, None] * np.array(step)
    return make_motion(local, root, height)


L_RES = 0.02


def box_voxels(bounds, l_res):
    lo = np.ceil(np.asarray(bounds[0]) / l_res - 0.5).astype(int)
    hi = np.floor(np.asarray(bounds[1]) / l_res - 0.5).astype(int)
    return np.argwhere(np.ones(hi - lo + 1, dtype=bool)) + lo


def as_set(ijk):
    return set(map(tuple, np.asarray(ijk).tolist()))


def exact_hull(el: Ellipsoids, rig, l_res, bounds):
    """Voxel centres inside every camera's viewing cone of the solids (analytic ray casting, no pixels)."""
    ijk = box_voxels(bounds, l_res)
    x = (ijk + 0.5) * l_res
    inside = np.ones(len(x), dtype=bool)
    for cam in rig:
        d = x - cam.centre
        hit = np.zeros(len(x), dtype=bool)
        for c, rot, r in zip(el.centres, el.rotations, el.radii, strict=True):
            o, dd = (rot.T @ (cam.centre - c)) / r, (d @ rot) / r
            a, b, cc = (dd * dd).sum(1), dd @ o, o @ o
            hit |= (b * b - a * (cc - 1.0) >= 0) & (b < 0)
        inside &= hit
    return ijk[inside]


def volume(el: Ellipsoids) -> float:
    """Total volume of the solids in cubic metres, overlaps counted twice: sum of 4/3 pi a b c."""
    return float(4.0 / 3.0 * np.pi * np.prod(np.broadcast_to(el.radii, el.centres.shape), axis=-1).sum())


def without_frame(seq, f):
    """The sequence with frame ``f``'s voxels removed (an empty hull)."""
    a, b = seq.offsets[f], seq.offsets[f + 1]
    ba, bb = seq.basis_offsets[f], seq.basis_offsets[f + 1]
    offsets = seq.offsets.copy()
    offsets[f + 1 :] -= b - a
    basis_offsets = seq.basis_offsets.copy()
    basis_offsets[f + 1 :] -= bb - ba
    empty = seq.empty.copy()
    empty[f] = True
    return VoxelSequence(
        l_res=seq.l_res, h_sub=seq.h_sub, h_sub_frame=seq.h_sub_frame, ijk=np.delete(seq.ijk, np.s_[a:b], axis=0),
        offsets=offsets, surface=np.delete(seq.surface, np.s_[a:b]), basis=np.delete(seq.basis, np.s_[ba:bb]),
        basis_offsets=basis_offsets, empty=empty, shifts=seq.shifts,
    )  # fmt: skip


SPHERE = Ellipsoids(("sphere",), np.array([[0.0, 1.0, 0.0]]), np.eye(3)[None], np.full((1, 3), 0.3))


VOLUME_BOX = [[-0.5, 0.45, -0.5], [0.5, 1.55, 0.5]]


def mvrvm_toy(n=200, noise=0.1, seed=0):
    """MVRVM test data: three functions of one input (sinc, a line, a cosine) with Gaussian noise, and their
    clean values."""
    rng = np.random.default_rng(seed)
    x = np.sort(rng.uniform(-10, 10, n))[:, None]
    clean = np.stack([np.sinc(x[:, 0] / np.pi), 0.05 * x[:, 0], np.cos(x[:, 0] / 2)], axis=1)
    return x, clean + noise * rng.standard_normal(clean.shape), clean


def mvrvm_log_ml(phi, y, alpha, beta):
    """The MVRVM's log marginal likelihood by brute force: sum_p log N(y_p | 0, I / beta_p + Phi A^-1 Phi')."""
    total = 0.0
    for p in range(y.shape[1]):
        c = np.eye(len(y)) / beta[p] + (phi / alpha) @ phi.T
        _, logdet = np.linalg.slogdet(c)
        total += -0.5 * (len(y) * np.log(2 * np.pi) + logdet + y[:, p] @ np.linalg.solve(c, y[:, p]))
    return total


# --- running the command and the workflow in a subprocess ---


def run_voxpose(*args, cwd=None):
    """``voxpose ARGS`` in a subprocess (``python -m voxpose``), output captured."""
    return subprocess.run([sys.executable, "-m", "voxpose", *map(str, args)], capture_output=True, text=True, cwd=cwd)


def one_line_error(proc, *fragments):
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("voxpose: error: ")
    for fragment in fragments:
        assert fragment in lines[0]


def snakemake(workdir, *args, configfiles=(), check=True):
    """Run Snakemake on the quick config (plus ``configfiles``, merged in order: one --configfile option)."""
    files = ["config/quick.yaml", *map(str, configfiles)]
    cmd = [sys.executable, "-m", "snakemake", "--cores", "2", *args, "--configfile", *files]
    # the rules call `voxpose`: the one installed beside this Python, running the package copy in `workdir`
    # (tests edit that copy to see which rules an edit reruns)
    env = os.environ | {
        "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}",
        "PYTHONPATH": str(workdir),
    }
    proc = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, env=env)
    if check and proc.returncode != 0:
        raise AssertionError(f"snakemake {' '.join(args)} failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-6000:]}")
    return proc


def scheduled(workdir, *configfiles, args=()) -> dict:
    """Rules (and job counts) a dry run would execute with the quick config plus ``configfiles``."""
    out = snakemake(workdir, "-n", *args, configfiles=configfiles).stdout
    if "Nothing to be done" in out:
        return {}
    table = out.split("Job stats:", 1)[1]
    rows = re.finditer(r"^(\w+)\s+(\d+)\s*$", table, re.M)
    return {m.group(1): int(m.group(2)) for m in rows if m.group(1) != "total"}


def copy_workflow(work: Path) -> Path:
    """A copy of the workflow and the package in ``work``, to run Snakemake in."""
    for item in ("Snakefile", "workflow", "config", "voxpose"):
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, work / item)
    return work


GENERATED_MAP = {
    "root": "Hips", "neck": "Neck", "head_top": "Head", "lshoulder": "LeftArm", "lelbow": "LeftForeArm",
    "lwrist": "LeftHand", "lhand_tip": "LeftHand", "lhip": "LeftUpLeg", "lknee": "LeftLeg", "lankle": "LeftFoot",
    "ltoe": "LeftToe",
}  # fmt: skip
GENERATED_MAP |= {"r" + k[1:]: v.replace("Left", "Right") for k, v in GENERATED_MAP.items() if k[0] == "l"}
"""The generated skeleton's joint map written out, for tests that load renamed copies through a config map."""
