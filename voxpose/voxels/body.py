"""The articulated body model of Section 6: ellipsoids and a sphere attached to the canonical skeleton.

Section 6 generates its silhouettes by projecting "an articulated body model represented by ellipsoids
and spheres". The paper gives no shapes or sizes, so this module fixes them: 16 solids on the 14
canonical joints and 5 end points of ``voxpose.motion.canon``,

=========================  ==========================  ===========
segment                    spans (a -> b)               frame owner
=========================  ==========================  ===========
pelvis, abdomen, chest     root -> neck (three parts)   root, root, neck
head (a sphere)            neck -> head_top             neck
l/r upperarm               shoulder -> elbow            shoulder
l/r forearm                elbow -> wrist               elbow
l/r hand                   wrist -> hand tip            wrist
l/r thigh                  hip -> knee                  hip
l/r shin                   knee -> ankle                knee
l/r foot                   ankle -> toe                 ankle
=========================  ==========================  ===========

The points ``a`` and ``b`` are anatomical landmarks, not the raw joints (``voxpose.voxels.landmarks``): the
root is the pelvis centre between the hip joints, the neck the base of the neck, the shoulders and hips
the glenohumeral and hip joint centres at anthropometric widths, with the limbs hanging from them. So
the same person gets the same body whichever skeleton family carries the motion.

Each solid's first axis (its length) lies along its segment ``a -> b``; the two cross-section axes (its
width and depth) come from the owning joint's canonical world rotation, so a flattened torso, hand or
foot turns with the body. Precisely, with ``B`` the solid's axes in the T-pose (columns: length, width,
depth) and ``R`` the owner's rotation, the solid's axes are ``minimal_rotation(R @ B[:, 0], d) @ R @ B``
with ``d`` the unit segment direction: exactly ``R @ B`` when the rotation already carries the T-pose
direction onto the segment (as the canonical limb rotations do), and otherwise the smallest correction
that puts the length axis on the segment (the chest, whose frame is the neck's, is the one such case by
design: its width follows the shoulder line while its length follows the spine).

Sizes (``DEFAULT_PROPORTIONS``): along the segment, a solid spans the fractions ``start .. end`` of
``a -> b`` (below 0 or above 1 reaches past a joint, e.g. the heel behind the ankle); its cross-section
semi-axes ``width`` and ``depth`` are fractions of the subject's standing height, so that the body
scales with the subject (Section 4's l_res = h_sub / 60 then gives the same voxel counts for every
subject). The head sphere has radius ``radius`` x height and its top touches ``head_top``. The
defaults are calibrated so that a subject carved at h/60 from the default rig
(``voxpose.voxels.cameras.circular_rig``) gives the counts of the paper's Figure 2, about 4000 occupied and 2000
surface voxels. ``benchmarks/bench_render_carve.py`` measured 4124 occupied (3465-5489) and 2055 surface
voxels (1808-2625) per frame on generated walking, drunken, spiral, jogging and jumping motions of a
1.75 m subject, and 3460 / 1777 on shared CMU and Bandai captures (their skeletons have shorter trunks).
That takes a body of 0.083 m^3 at 1.75 m, a heavy-set adult: with cross-sections 1/1.14 as wide (0.065
m^3, about an average 70 kg adult) the counts are about 3000 / 1650.
"""

from dataclasses import dataclass

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.motion import canon
from voxpose.motion.data import MotionData
from voxpose.motion.rotations import minimal_rotation
from voxpose.voxels.body_variation import vary_girths, vary_lengths
from voxpose.voxels.landmarks import anatomical_points

_X, _Y, _Z = np.eye(3)

# name: (a, b, owner joint, T-pose length direction, T-pose width direction)
_SEGMENTS = {
    "pelvis": ("root", "neck", "root", _Y, _X),
    "abdomen": ("root", "neck", "root", _Y, _X),
    "chest": ("root", "neck", "neck", _Y, _X),
    "head": ("neck", "head_top", "neck", _Y, _X),
    "lupperarm": ("lshoulder", "lelbow", "lshoulder", _X, _Z),
    "lforearm": ("lelbow", "lwrist", "lelbow", _X, _Z),
    "lhand": ("lwrist", "lhand_tip", "lwrist", _X, _Z),
    "rupperarm": ("rshoulder", "relbow", "rshoulder", -_X, _Z),
    "rforearm": ("relbow", "rwrist", "relbow", -_X, _Z),
    "rhand": ("rwrist", "rhand_tip", "rwrist", -_X, _Z),
    "lthigh": ("lhip", "lknee", "lhip", -_Y, _X),
    "lshin": ("lknee", "lankle", "lknee", -_Y, _X),
    "lfoot": ("lankle", "ltoe", "lankle", _Z, _X),
    "rthigh": ("rhip", "rknee", "rhip", -_Y, _X),
    "rshin": ("rknee", "rankle", "rknee", -_Y, _X),
    "rfoot": ("rankle", "rtoe", "rankle", _Z, _X),
}
SEGMENTS = tuple(_SEGMENTS)
SPHERES = ("head",)

_LIMBS = {
    # start, end: fractions of the segment; width, depth: semi-axes as fractions of the standing height
    "upperarm": {"start": -0.1, "end": 1.05, "width": 0.035, "depth": 0.035},
    "forearm": {"start": -0.05, "end": 1.05, "width": 0.028, "depth": 0.027},
    "hand": {"start": -0.05, "end": 1.0, "width": 0.030, "depth": 0.013},
    "thigh": {"start": -0.05, "end": 1.05, "width": 0.051, "depth": 0.051},
    "shin": {"start": -0.05, "end": 1.05, "width": 0.034, "depth": 0.036},
    "foot": {"start": -0.35, "end": 1.05, "width": 0.030, "depth": 0.027},
}
DEFAULT_PROPORTIONS = {
    "pelvis": {"start": -0.3, "end": 0.35, "width": 0.104, "depth": 0.073},
    "abdomen": {"start": 0.2, "end": 0.7, "width": 0.091, "depth": 0.067},
    "chest": {"start": 0.45, "end": 1.05, "width": 0.110, "depth": 0.073},
    "head": {"radius": 0.063},
    **{side + limb: dict(sizes) for side in ("l", "r") for limb, sizes in _LIMBS.items()},
}
"""Per-segment sizes (see the module docstring); a config may override any subset."""


@dataclass
class Ellipsoids:
    """Solids of the body model, for a sequence (leading frame axis F) or one frame (no frame axis).

    Attributes
    ----------
    names : segment names, length E.
    centres : (F, E, 3) or (E, 3) centres in metres, world frame.
    rotations : (F, E, 3, 3) or (E, 3, 3); column k is the world direction of semi-axis k.
    radii : (E, 3) or (F, E, 3) semi-axes in metres (length, width, depth).
    """

    names: tuple
    centres: np.ndarray
    rotations: np.ndarray
    radii: np.ndarray

    @property
    def n_frames(self) -> int:
        """Number of frames (1 for a single frame without a frame axis)."""
        return 1 if self.centres.ndim == 2 else int(self.centres.shape[0])

    def frame(self, f: int) -> "Ellipsoids":
        """The solids of frame ``f`` (arrays without the frame axis)."""
        radii = self.radii[f] if self.radii.ndim == 3 else self.radii
        return Ellipsoids(self.names, self.centres[f], self.rotations[f], radii)

    def translated(self, shift) -> "Ellipsoids":
        """A copy moved by ``shift``: (3,) for all frames, or (F, 3) one per frame (metres)."""
        shift = np.asarray(shift, dtype=float)
        if shift.ndim == 2:
            shift = shift[:, None, :]
        return Ellipsoids(self.names, self.centres + shift, self.rotations, self.radii)

    def shape_matrices(self) -> np.ndarray:
        """``Sigma = R diag(r^2) R^T`` (..., E, 3, 3): the solid is ``{x : (x-c)^T Sigma^-1 (x-c) <= 1}``."""
        radii = np.broadcast_to(self.radii, self.centres.shape)
        return (self.rotations * radii[..., None, :] ** 2) @ np.swapaxes(self.rotations, -1, -2)


def resolve_proportions(overrides=None) -> dict:
    """``DEFAULT_PROPORTIONS`` updated by ``overrides`` (``{segment: {key: value}}``), validated."""
    table = {name: dict(sizes) for name, sizes in DEFAULT_PROPORTIONS.items()}
    for name, sizes in (overrides or {}).items():
        if name not in table:
            raise VoxposeError(f"body proportions: unknown segment {name!r} (known: {', '.join(SEGMENTS)})")
        if not isinstance(sizes, dict):
            raise VoxposeError(f"body proportions: {name} must be a mapping of sizes, got {sizes!r}")
        for key, value in sizes.items():
            if key not in table[name]:
                known = ", ".join(table[name])
                raise VoxposeError(f"body proportions: unknown key {name}.{key} (known: {known})")
            if isinstance(value, bool) or not isinstance(value, int | float) or not np.isfinite(value):
                raise VoxposeError(f"body proportions: {name}.{key} must be a number, got {value!r}")
            table[name][key] = float(value)
    for name, sizes in table.items():
        for key in ("width", "depth", "radius"):
            if key in sizes and sizes[key] <= 0:
                raise VoxposeError(f"body proportions: {name}.{key} must be positive, got {sizes[key]}")
        if "start" in sizes and sizes["end"] <= sizes["start"]:
            raise VoxposeError(f"body proportions: {name}.end must exceed {name}.start")
    return table


def _pose_arrays(motion):
    """(positions, rotations, ends, height, label) from a ``MotionData`` or a mapping of the same keys."""
    if isinstance(motion, MotionData):
        arrays = {k: getattr(motion, k) for k in ("positions", "rotations", "ends", "height")}
        label = f"motion {motion.name}"
    elif isinstance(motion, dict):
        missing = [k for k in ("positions", "rotations", "ends", "height") if k not in motion]
        if missing:
            raise VoxposeError(f"body model: pose arrays lack key(s) {', '.join(missing)}")
        arrays, label = motion, "pose arrays"
    else:
        raise VoxposeError(f"body model: expected a MotionData or a dict of arrays, got {type(motion).__name__}")
    positions = np.asarray(arrays["positions"], dtype=float)
    rotations = np.asarray(arrays["rotations"], dtype=float)
    ends = np.asarray(arrays["ends"], dtype=float)
    height = float(arrays["height"])
    n_frames = positions.shape[0] if positions.ndim == 3 else -1
    expected = {
        "positions": (positions, (n_frames, canon.N_JOINTS, 3)),
        "rotations": (rotations, (n_frames, canon.N_JOINTS, 3, 3)),
        "ends": (ends, (n_frames, len(canon.ENDS), 3)),
    }
    for key, (array, shape) in expected.items():
        if array.shape != shape:
            raise VoxposeError(f"body model: {label}: {key} has shape {array.shape}, expected (F, ...) {shape}")
        bad = ~np.isfinite(array.reshape(n_frames, -1)).all(axis=1)
        if bad.any():
            raise VoxposeError(f"body model: {label}: {key} not finite in frame {int(np.argmax(bad))}")
    if not np.isfinite(height) or height <= 0:
        raise VoxposeError(f"body model: {label}: height must be positive, got {height}")
    return positions, rotations, ends, height, label


def body_ellipsoids(motion, proportions=None, variation=None) -> Ellipsoids:
    """The body model of every frame of a motion (Section 6), vectorised over frames.

    Parameters
    ----------
    motion : ``MotionData``, or a dict with ``positions`` (F, 14, 3), ``rotations`` (F, 14, 3, 3),
        ``ends`` (F, 5, 3) in metres and canonical world frames, and ``height`` (metres).
    proportions : overrides of ``DEFAULT_PROPORTIONS`` (``{segment: {key: value}}``).
    variation : this motion's girth and length factors (``voxels.body_variation.BodyVariation.draw``), or None.

    Returns
    -------
    Ellipsoids with centres (F, 16, 3), rotations (F, 16, 3, 3) and radii (F, 16, 3), in ``SEGMENTS``
    order. A segment of zero length is an error naming the frame.
    """
    positions, rotations, ends, height, label = _pose_arrays(motion)
    table = resolve_proportions(proportions)
    positions, ends = anatomical_points(positions, ends, height, label)
    if variation is not None:
        table = vary_girths(table, variation["girth"])
        positions, ends = vary_lengths(positions, ends, variation["length"])
    points = np.concatenate([positions, ends], axis=1)
    index = {name: i for i, name in enumerate(canon.JOINTS + canon.ENDS)}
    a = points[:, [index[s[0]] for s in _SEGMENTS.values()]]
    b = points[:, [index[s[1]] for s in _SEGMENTS.values()]]
    owner = rotations[:, [canon.INDEX[s[2]] for s in _SEGMENTS.values()]]
    along = np.stack([s[3] for s in _SEGMENTS.values()])
    width = np.stack([s[4] for s in _SEGMENTS.values()])
    base = np.stack([along, width, np.cross(along, width)], axis=-1)  # (E, 3, 3), columns

    vec = b - a
    length = np.linalg.norm(vec, axis=-1)
    if (length < 1e-6).any():
        f, e = np.argwhere(length < 1e-6)[0]
        raise VoxposeError(f"body model: {label}: segment {SEGMENTS[e]} has zero length in frame {f}")
    direction = vec / length[..., None]
    frames = owner @ base
    axes = minimal_rotation(frames[..., 0], direction) @ frames

    start = np.array([table[n].get("start", 0.0) for n in SEGMENTS])
    end = np.array([table[n].get("end", 1.0) for n in SEGMENTS])
    centres = a + vec * (0.5 * (start + end))[:, None]
    radii = np.empty(length.shape + (3,))
    radii[..., 0] = 0.5 * (end - start) * length
    radii[..., 1] = height * np.array([table[n].get("width", 0.0) for n in SEGMENTS])
    radii[..., 2] = height * np.array([table[n].get("depth", 0.0) for n in SEGMENTS])
    for name in SPHERES:
        e = SEGMENTS.index(name)
        radius = height * table[name]["radius"]
        radii[:, e] = radius
        centres[:, e] = b[:, e] - radius * direction[:, e]
    return Ellipsoids(SEGMENTS, centres, axes, radii)
