"""The BVH skeleton that estimated poses are written on: the canonical 14-joint body as a standard BVH file.

The regressor estimates the 42 angles of y' (Section 2), not a body: to be viewed (Blender, any BVH viewer)
they need a skeleton. Ours is the canonical one of ``voxpose.motion.canon`` written as a BVH hierarchy whose rest
pose is the canonical T-pose (world-aligned bone frames, facing +Z, left at +X, Y up, metres), so a joint's
rotation channels *are* its three canonical angles, in its ``motion.canon.EULER_ORDERS`` order (``YXZ`` joints
carry ``Yrotation Xrotation Zrotation``, ``XYZ`` joints ``Xrotation Yrotation Zrotation``). Reading the
channels back (``angles_from_bvh``) gives the written angles exactly (to the printed digits), and the
joint positions a viewer draws are the forward kinematics of y'
(``voxpose.motion.pose_kinematics``) used by the metrics.

Joint names are those of the generated skeleton (``Hips``, ``Neck``, ``LeftArm``, ...; ``joint_map``'s
``generated`` preset), so ``voxpose motion`` and ``motion.load.load_motion`` read the files like any
other BVH. Two helper joints hold ends and never rotate (channels always 0): ``Head`` (its End Site is the
head top) and ``LeftToe``/``RightToe`` (End Site: the toe); the hand tip is ``LeftHand``'s End Site.

Which body (our choice; the paper draws its estimates on its own mocap skeleton): the training subjects'
skeleton, ``from_motions``, i.e. per joint the median over the training motions of their canonical offsets
(``MotionData.offsets``) and of the end lengths (head, hand, foot), made left-right symmetric (means of
the mirrored left and right sides) and with every limb bone along its T-pose direction. Symmetry makes the
T-pose exactly canonical (hips and shoulders level), so ``load_motion`` of a written file finds the written
angles again wherever they have no limb twist (canonical angles never have: ``voxpose.motion.canonical_pose``);
estimated angles can carry a small twist, which a position-based reader cannot see and re-expresses in the
child joints' angles.
"""

from dataclasses import dataclass

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh, BvhJoint
from voxpose.motion import canon

_ROOT_POSITION = ("Xposition", "Yposition", "Zposition")
_NAMES = {
    "root": "Hips", "neck": "Neck",
    "lshoulder": "LeftArm", "lelbow": "LeftForeArm", "lwrist": "LeftHand",
    "rshoulder": "RightArm", "relbow": "RightForeArm", "rwrist": "RightHand",
    "lhip": "LeftUpLeg", "lknee": "LeftLeg", "lankle": "LeftFoot",
    "rhip": "RightUpLeg", "rknee": "RightLeg", "rankle": "RightFoot",
}  # fmt: skip
# end -> (canonical joint it hangs from, helper joint carrying its End Site or None: the joint's own End Site)
_ENDS = {
    "head_top": ("neck", "Head"),
    "lhand_tip": ("lwrist", None),
    "rhand_tip": ("rwrist", None),
    "ltoe": ("lankle", "LeftToe"),
    "rtoe": ("rankle", "RightToe"),
}
_MIRROR = np.array([-1.0, 1.0, 1.0])


def _channels(joint: str) -> tuple[str, ...]:
    return tuple(f"{axis}rotation" for axis in canon.EULER_ORDERS[canon.INDEX[joint]])


@dataclass(frozen=True)
class OutputSkeleton:
    """The output body, metres.

    Attributes
    ----------
    offsets : (14, 3) each joint's offset from its canonical parent in the parent's canonical frame (root
        row zero), as ``MotionData.offsets``.
    end_lengths : (5,) distances of ``motion.canon.ENDS`` from the joint they hang from (neck, wrists, ankles);
        each end lies along its joint's T-pose direction (up for the head).
    """

    offsets: np.ndarray
    end_lengths: np.ndarray

    def __post_init__(self):
        offsets, lengths = np.asarray(self.offsets, float), np.asarray(self.end_lengths, float)
        if offsets.shape != (canon.N_JOINTS, 3) or lengths.shape != (len(canon.ENDS),):
            raise VoxposeError(f"output skeleton: offsets (14, 3) and end lengths (5,), got {offsets.shape}, "
                               f"{lengths.shape}")  # fmt: skip
        if not (np.isfinite(offsets).all() and np.isfinite(lengths).all() and (lengths > 0).all()):
            raise VoxposeError("output skeleton: offsets must be finite and end lengths positive")

    @classmethod
    def from_motions(cls, motions) -> "OutputSkeleton":
        """The training subjects' skeleton (module docstring) from ``MotionData`` objects."""
        motions = list(motions)
        if not motions:
            raise VoxposeError("output skeleton: no motions to take the skeleton from")
        offsets = np.median([m.offsets for m in motions], axis=0)
        lengths = np.median([_end_lengths(m) for m in motions], axis=0)
        return cls(*_symmetric(offsets, lengths))

    def scaled(self, factor: float) -> "OutputSkeleton":
        """The same skeleton ``factor`` times as large (offsets and end lengths): another subject's size."""
        if not (np.isfinite(factor) and factor > 0):
            raise VoxposeError(f"output skeleton: scale factor must be positive, got {factor!r}")
        return OutputSkeleton(self.offsets * factor, np.asarray(self.end_lengths, float) * factor)

    def bvh(self, angles, root_positions, frame_time: float) -> Bvh:
        """A BVH of y' (F, 42) degrees with the root at ``root_positions`` (F, 3) metres."""
        angles = np.asarray(angles, dtype=float)
        root = np.asarray(root_positions, dtype=float)
        n = len(angles)
        if angles.shape != (n, canon.N_ANGLES) or root.shape != (n, 3):
            raise VoxposeError(f"output skeleton: angles (F, 42) and root positions (F, 3), got {angles.shape} "
                               f"and {root.shape}")  # fmt: skip
        joints, columns = [], []
        index = {}

        def add(name, parent, offset, channels, end_site=None, values=None):
            index[name] = len(joints)
            joints.append(BvhJoint(name, -1 if parent is None else index[parent], np.asarray(offset, float),
                                   channels, None if end_site is None else np.asarray(end_site, float)))  # fmt: skip
            if values is not None:
                columns.append(values)
            elif channels:
                columns.append(np.zeros((n, len(channels))))

        def joint(j, parent):
            k = canon.INDEX[j]
            site = {"lwrist": "lhand_tip", "rwrist": "rhand_tip"}.get(j)
            end = None if site is None else self.end_lengths[canon.ENDS.index(site)] * canon.TPOSE_DIRECTIONS[k]
            add(_NAMES[j], parent, self.offsets[k], _channels(j), end, angles[:, 3 * k : 3 * k + 3])

        def helper(end, parent_joint):
            anchor, name = _ENDS[end]
            half = 0.5 * self.end_lengths[canon.ENDS.index(end)] * canon.TPOSE_DIRECTIONS[canon.INDEX[anchor]]
            add(name, parent_joint, half, _channels(anchor), half)

        add("Hips", None, np.zeros(3), _ROOT_POSITION + _channels("root"), None,
            np.concatenate([root, angles[:, 0:3]], axis=1))  # fmt: skip
        joint("neck", "Hips")
        helper("head_top", "Neck")
        for side in "lr":
            joint(f"{side}shoulder", "Neck")
            joint(f"{side}elbow", _NAMES[f"{side}shoulder"])
            joint(f"{side}wrist", _NAMES[f"{side}elbow"])
        for side in "lr":
            joint(f"{side}hip", "Hips")
            joint(f"{side}knee", _NAMES[f"{side}hip"])
            joint(f"{side}ankle", _NAMES[f"{side}knee"])
            helper(f"{side}toe", _NAMES[f"{side}ankle"])
        return Bvh(joints=joints, frame_time=float(frame_time), motion=np.concatenate(columns, axis=1))


def angles_from_bvh(bvh: Bvh) -> tuple[np.ndarray, np.ndarray]:
    """y' (F, 42) and root positions (F, 3) from the channels of a BVH written by ``OutputSkeleton.bvh``."""
    names = [j.name for j in bvh.joints]
    start = np.cumsum([0] + [len(j.channels) for j in bvh.joints])
    angles = np.empty((bvh.n_frames, canon.N_ANGLES))
    for j, k in canon.INDEX.items():
        name = _NAMES[j]
        if name not in names:
            raise VoxposeError(f"BVH: no joint {name}: not written on voxpose's output skeleton")
        i = names.index(name)
        channels = bvh.joints[i].channels[-3:]
        if channels != _channels(j):
            raise VoxposeError(f"BVH: joint {name} has channels {channels}, the output skeleton's are {_channels(j)}")
        angles[:, 3 * k : 3 * k + 3] = bvh.motion[:, start[i + 1] - 3 : start[i + 1]]
    return angles, bvh.motion[:, :3].copy()


def _end_lengths(motion) -> np.ndarray:
    """Median distance of each end from the joint it hangs from, (5,) metres."""
    anchors = [canon.INDEX[_ENDS[e][0]] for e in canon.ENDS]
    return np.median(np.linalg.norm(motion.ends - motion.positions[:, anchors], axis=-1), axis=0)


def _symmetric(offsets: np.ndarray, lengths: np.ndarray):
    """Left-right means of mirrored offsets and end lengths; limb bones along their T-pose directions."""
    offsets = offsets.copy()
    parents = canon.PARENTS
    for j in canon.JOINTS:
        if not j.startswith("l"):
            continue
        left, right = canon.INDEX[j], canon.INDEX["r" + j[1:]]
        parent = canon.JOINTS[parents[left]]
        if parent in ("root", "neck"):  # hips and shoulders: any direction, mirrored
            mean = 0.5 * (offsets[left] + _MIRROR * offsets[right])
        else:  # limb bones: along the parent's T-pose direction
            length = 0.5 * (np.linalg.norm(offsets[left]) + np.linalg.norm(offsets[right]))
            mean = length * canon.TPOSE_DIRECTIONS[parents[left]]
        offsets[left], offsets[right] = mean, _MIRROR * mean
    offsets[canon.INDEX["neck"]] = [0.0, np.linalg.norm(offsets[canon.INDEX["neck"]]), 0.0]
    lengths = lengths.copy()
    for side_pair in (("lhand_tip", "rhand_tip"), ("ltoe", "rtoe")):
        i, k = (canon.ENDS.index(e) for e in side_pair)
        lengths[i] = lengths[k] = 0.5 * (lengths[i] + lengths[k])
    return offsets, lengths
