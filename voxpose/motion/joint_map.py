"""Which joints of a source skeleton are the 14 canonical joints and 5 ends of Section 2 (``voxpose.motion.canon``).

Built-in presets, detected from the joint names (a preset fits when every joint it names exists):

* ``cmu``: the CMU database in B. Hahne's cgspeed BVH conversion (31 joints). The canonical neck is
  CMU's ``Neck``, the base of the neck at the top of the thoracic spine where the clavicles branch off
  (it shares its position with ``Spine1``); ``Neck1`` is 8 cm higher, mid-neck. ``Neck`` matches the
  neck of the Bandai and generated skeletons (base of the neck) and keeps the head segment
  (neck -> head top) the whole head and neck, as the body model draws it. Ends: ``Head``'s End Site,
  the index finger's End Site (``LeftHandIndex1``; about the knuckles), ``LeftToeBase``'s End Site.
  The files start with a reference-pose frame (``voxpose.motion.reference_pose``).
* ``generated``: the skeleton of ``voxpose.motion.generated_skeleton`` (CMU-like names, ``LeftToe``, End Sites
  on ``Head``, the hands and the toes).
* ``bandai``: the Bandai Namco Research Motion Dataset (22 joints); the root is ``Hips`` (the static top
  joint ``joint_Root`` is ignored). Its Head, Hand and Toes End Sites have zero length, so those ends
  are estimated beyond the named joints as below.

Any other skeleton needs a map from the config, ``{canonical name: source joint name}`` for the 14 joints
and optionally the ends. Extra source joints (fingers, eyes, spine segments, clavicles) are ignored:
they still move the mapped joints through forward kinematics.

End Site points. A value ``<joint>/end`` names the point at ``<joint>``'s End Site, for skeletons whose
chains stop short of a canonical joint: a rig with no hand joints, whose forearm ends in an End Site at
the wrist, maps ``lwrist: forearm.L/end``. The point moves rigidly with ``<joint>`` (its world rotation is
``<joint>``'s, its incoming bone the End Site offset), so an end estimated from it continues that bone:
with no hand the hand tip continues the forearm, and the wrist angles are those of a straight wrist.
The canonical angles are measured towards the mapped points and ends (``canonical_pose``), so the map
defines them: a wrist angle points the wrist frame at the mapped hand tip, a neck angle at the head top. The
hand tips are then turned, with their joints, onto the rest pose's straight hand (``neutral_ends``), so a
hand end off the hand's axis (a knuckle) does not read as a bent wrist.

An end named as source joint ``N`` is ``N``'s End Site. When ``N`` has no End Site or a zero-length one,
or no ``N`` is given (then ``N`` is the end's anchor: the neck for the head top, the wrist for a hand
tip, the ankle for a toe), the end is estimated so that it moves with ``N``:

    end(t) = p_N(t) + W_N(t) @ (u * l),

with ``W_N`` the joint's world rotation and ``u`` a direction in its local frame: the direction of the
bone into ``N`` (its OFFSET, or its nearest ancestor's non-zero OFFSET), i.e. the end continues that
bone straight in the rest pose. This holds both for world-aligned rest poses (CMU) and for rigs whose
bones lie along a local axis (Bandai). For a toe with no ``N`` the direction is the rest pose's forward
(the pelvis frame's z of ``canonical_pose`` in the rest pose), which assumes the rest pose's feet point
forward. The length ``l`` puts the end at a fixed proportion of a segment from its anchor (less the
anchor -> ``N`` distance when ``N`` lies beyond the anchor; lengths are medians over the frames, so they
do not depend on the rest pose). The proportions are the medians over subjects of the measured End
Sites of the 17 shared CMU files (8 subjects): head top = neck + 0.35 x leg length (hip -> knee ->
ankle, mean of both sides; range 0.31-0.36), hand tip = wrist + 0.36 x forearm (range 0.30-0.54),
toe = ankle + 0.42 x shank (range 0.37-0.47), so estimated ends mean the same points as CMU's.
"""

from dataclasses import dataclass

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.io.bvh import Bvh, BvhJoint
from voxpose.motion import canon
from voxpose.motion.bvh_kinematics import forward_kinematics, rest_pose
from voxpose.motion.neutral_ends import neutral_ends, rest_corrections

# end: (anchor joint, proportion, segment the proportion applies to: "leg" or a (from, to) joint pair)
_END_RULES = {
    "head_top": ("neck", 0.35, "leg"),
    "lhand_tip": ("lwrist", 0.36, ("lelbow", "lwrist")),
    "rhand_tip": ("rwrist", 0.36, ("relbow", "rwrist")),
    "ltoe": ("lankle", 0.42, ("lknee", "lankle")),
    "rtoe": ("rankle", 0.42, ("rknee", "rankle")),
}
_ZERO = 1e-9
END_SITE_SUFFIX = "/end"  # "<joint>/end": the point at that joint's End Site (module docstring)


@dataclass(frozen=True)
class JointMap:
    """Source joint names for the canonical joints and ends.

    Attributes
    ----------
    preset : ``"cmu"``, ``"generated"``, ``"bandai"`` or ``"config"``.
    joints : 14 source joint names in ``motion.canon.JOINTS`` order.
    ends : 5 source joint names (or None: estimated from the anchor) in ``motion.canon.ENDS`` order.
    """

    preset: str
    joints: tuple[str, ...]
    ends: tuple[str | None, ...]


def _preset(name: str, central: dict, left: dict, right_of) -> JointMap:
    """A preset from its central names, its left-side names (keys ``l...``) and the left -> right rename."""
    names = {**central, **left, **{"r" + key[1:]: right_of(n) for key, n in left.items()}}
    return JointMap(
        preset=name,
        joints=tuple(names[j] for j in canon.JOINTS),
        ends=tuple(names[e] for e in canon.ENDS),
    )


_CMU_LEFT = {
    "lshoulder": "LeftArm",
    "lelbow": "LeftForeArm",
    "lwrist": "LeftHand",
    "lhip": "LeftUpLeg",
    "lknee": "LeftLeg",
    "lankle": "LeftFoot",
}
PRESETS = (
    _preset(
        "cmu",
        {"root": "Hips", "neck": "Neck", "head_top": "Head"},
        {**_CMU_LEFT, "lhand_tip": "LeftHandIndex1", "ltoe": "LeftToeBase"},
        lambda n: n.replace("Left", "Right"),
    ),
    _preset(
        "generated",
        {"root": "Hips", "neck": "Neck", "head_top": "Head"},
        {**_CMU_LEFT, "lhand_tip": "LeftHand", "ltoe": "LeftToe"},
        lambda n: n.replace("Left", "Right"),
    ),
    _preset(
        "bandai",
        {"root": "Hips", "neck": "Neck", "head_top": "Head"},
        {
            "lshoulder": "UpperArm_L",
            "lelbow": "LowerArm_L",
            "lwrist": "Hand_L",
            "lhip": "UpperLeg_L",
            "lknee": "LowerLeg_L",
            "lankle": "Foot_L",
            "lhand_tip": "Hand_L",
            "ltoe": "Toes_L",
        },
        lambda n: n[:-2] + "_R",
    ),
)


def _names_used(jmap: JointMap) -> list[str]:
    return list(jmap.joints) + [e for e in jmap.ends if e is not None]


def _example_map() -> str:
    return "{" + ", ".join(f"{j}: <name>" for j in canon.JOINTS) + "}"


def _from_config(bvh: Bvh, joint_map, source: str) -> JointMap:
    if not isinstance(joint_map, dict):
        raise VoxposeError(f"{source}: joint_map must be a mapping {_example_map()}, got {type(joint_map).__name__}")
    known = set(canon.JOINTS) | set(canon.ENDS)
    unknown = sorted(str(k) for k in joint_map if k not in known)
    if unknown:
        raise VoxposeError(
            f"{source}: joint_map has unknown keys {unknown}; allowed: {', '.join(canon.JOINTS + canon.ENDS)}"
        )
    missing = [j for j in canon.JOINTS if j not in joint_map]
    if missing:
        raise VoxposeError(f"{source}: joint_map lacks {', '.join(missing)}; it must name all 14 joints")
    names = {j.name for j in bvh.joints} | set(_end_site_points(bvh))
    bad = {k: v for k, v in joint_map.items() if not isinstance(v, str) or v not in names}
    if bad:
        raise VoxposeError(
            f"{source}: joint_map names joints not in the skeleton: {bad}; skeleton joints and End Site points "
            f"(<joint>{END_SITE_SUFFIX}): {', '.join(sorted(names))}"
        )
    values = [joint_map[j] for j in canon.JOINTS]
    twice = sorted({v for v in values if values.count(v) > 1})
    if twice:
        raise VoxposeError(f"{source}: joint_map maps several canonical joints to {twice}")
    return JointMap(preset="config", joints=tuple(values), ends=tuple(joint_map.get(e) for e in canon.ENDS))


def resolve_joint_map(bvh: Bvh, joint_map: dict | None = None, *, source: str = "BVH") -> JointMap:
    """The joint map for ``bvh``: from the config when given, else the first preset that fits.

    ``source`` names the file in error messages. An unknown skeleton without a map raises a
    ``VoxposeError`` naming the canonical joints the closest preset could not find.
    """
    if joint_map is not None:
        return _from_config(bvh, joint_map, source)
    names = {j.name for j in bvh.joints}
    for preset in PRESETS:
        if all(n in names for n in _names_used(preset)):
            return preset
    closest = max(PRESETS, key=lambda p: sum(n in names for n in _names_used(p)))
    lacking = [f"{c} ({n})" for c, n in zip(canon.JOINTS, closest.joints, strict=True) if n not in names]
    lacking += [f"{c} ({n})" for c, n in zip(canon.ENDS, closest.ends, strict=True) if n not in names]
    raise VoxposeError(
        f"{source}: unknown skeleton: no built-in joint map fits (closest: {closest.preset}, "
        f"which could not match {', '.join(lacking)}); "
        f"add joint_map: {_example_map()} to the motions section of the config"
    )


def _end_site_points(bvh: Bvh) -> dict[str, int]:
    """``{"<joint>/end": joint index}`` for the joints with a non-zero End Site (unless a joint has that name)."""
    names = {j.name for j in bvh.joints}
    return {
        j.name + END_SITE_SUFFIX: i
        for i, j in enumerate(bvh.joints)
        if j.end_site is not None and np.linalg.norm(j.end_site) > _ZERO and j.name + END_SITE_SUFFIX not in names
    }


def _with_end_site_points(bvh: Bvh, jmap: JointMap, fk) -> tuple[Bvh, tuple]:
    """``bvh`` and its forward kinematics ``fk`` with each End Site point the map names appended as a joint.

    The appended joint is a child of the End Site's joint with the End Site as OFFSET and no channels (so the
    motion columns do not change), positioned at the End Site and rotated with its joint.
    """
    points = _end_site_points(bvh)
    used = [n for n in dict.fromkeys(_names_used(jmap)) if n in points]
    if not used:
        return bvh, fk
    positions, rotations, end_sites = fk
    parents = [points[n] for n in used]
    joints = list(bvh.joints) + [BvhJoint(n, p, bvh.joints[p].end_site, ()) for n, p in zip(used, parents, strict=True)]
    positions = np.concatenate([positions, np.stack([end_sites[p] for p in parents], axis=1)], axis=1)
    rotations = np.concatenate([rotations, rotations[:, parents]], axis=1)
    return Bvh(joints, bvh.frame_time, bvh.motion), (positions, rotations, end_sites)


def _indices(bvh: Bvh, names) -> list[int | None]:
    index = {j.name: i for i, j in enumerate(bvh.joints)}
    return [None if n is None else index[n] for n in names]


def _incoming_direction(bvh: Bvh, j: int) -> np.ndarray:
    """Unit direction of the bone into joint ``j``: its OFFSET, or its nearest ancestor's non-zero one."""
    while j >= 0:
        offset = bvh.joints[j].offset
        norm = np.linalg.norm(offset)
        if norm > _ZERO:
            return offset / norm
        j = bvh.joints[j].parent
    raise VoxposeError(f"joint map: joint {bvh.joints[0].name!r} and its chain have zero offsets")


def _rest_forward(rest_joints: np.ndarray) -> np.ndarray:
    """The rest pose's forward direction: z of the pelvis frame (x from the hips, y from root to neck)."""
    up = rest_joints[canon.INDEX["neck"]] - rest_joints[canon.INDEX["root"]]
    lateral = rest_joints[canon.INDEX["lhip"]] - rest_joints[canon.INDEX["rhip"]]
    forward = np.cross(lateral, up)
    norm = np.linalg.norm(forward)
    if norm <= _ZERO:
        raise VoxposeError("joint map: cannot tell forward in the rest pose (hips in line with the spine)")
    return forward / norm


def _median_distance(positions: np.ndarray, a: int, b: int) -> float:
    """Median over frames of the distance between joints ``a`` and ``b`` (a bone length, for rigid bones)."""
    return float(np.median(np.linalg.norm(positions[:, a] - positions[:, b], axis=-1)))


def _end_plan(bvh: Bvh, jmap: JointMap, positions: np.ndarray, rest: np.ndarray) -> list[tuple[int, np.ndarray | None]]:
    """For each end: (source joint N, None to use its End Site, or the local vector u * l to add to N).

    ``rest`` (J, 3) holds the joint positions of the rest pose. Lengths are medians over the frames of world
    distances, so they do not depend on the rest pose.
    """
    joint_idx = _indices(bvh, jmap.joints)
    canonical = {name: joint_idx[i] for name, i in canon.INDEX.items()}
    dist = lambda a, b: _median_distance(positions, canonical[a], canonical[b])  # noqa: E731
    leg = 0.5 * sum(dist(f"{s}hip", f"{s}knee") + dist(f"{s}knee", f"{s}ankle") for s in "lr")
    plan = []
    for end, n_idx in zip(canon.ENDS, _indices(bvh, jmap.ends), strict=True):
        anchor, proportion, segment = _END_RULES[end]
        a_idx = canonical[anchor]
        site = None if n_idx is None else bvh.joints[n_idx].end_site
        if site is not None and np.linalg.norm(site) > _ZERO:
            plan.append((n_idx, None))
            continue
        target = proportion * (leg if segment == "leg" else dist(*segment))
        if n_idx is None or n_idx == a_idx:
            n_idx = a_idx
            if end.endswith("toe"):
                direction = _rest_forward(rest[joint_idx])
            else:
                direction = _incoming_direction(bvh, n_idx)
            length = target
        else:
            direction = _incoming_direction(bvh, n_idx)
            length = max(target - _median_distance(positions, n_idx, a_idx), 0.0)
        plan.append((n_idx, direction * length))
    return plan


def _end_points(fk: tuple, plan: list) -> np.ndarray:
    """The ends (F, 5, 3) of forward kinematics ``fk`` placed by ``plan`` (``_end_plan``)."""
    positions, rotations, end_sites = fk
    ends = np.empty((positions.shape[0], len(canon.ENDS), 3))
    for e, (n_idx, local) in enumerate(plan):
        ends[:, e] = end_sites[n_idx] if local is None else positions[:, n_idx] + rotations[:, n_idx] @ local
    return ends


def skeleton_points(bvh: Bvh, jmap: JointMap, fk=None) -> tuple[np.ndarray, np.ndarray]:
    """World positions of the 14 canonical joints (F, 14, 3) and 5 ends (F, 5, 3), file units.

    ``fk`` is ``kinematics.forward_kinematics(bvh)`` when already computed. The hand tips and the head top are
    normalised to the rest pose's neutral directions (``voxpose.motion.neutral_ends``).
    """
    source = bvh
    bvh, fk = _with_end_site_points(source, jmap, forward_kinematics(source) if fk is None else fk)
    _, rest_fk = _with_end_site_points(source, jmap, forward_kinematics(rest_pose(source)))
    positions, rotations, _ = fk
    joint_idx = _indices(bvh, jmap.joints)
    joints = positions[:, joint_idx]
    if positions.shape[0] == 0:
        return joints, np.empty((0, len(canon.ENDS), 3))
    plan = _end_plan(bvh, jmap, positions, rest_fk[0][0])
    ends = _end_points(fk, plan)
    corrections = rest_corrections(rest_fk[0][0, joint_idx], _end_points(rest_fk, plan)[0])
    carriers = rotations[:, [n_idx for n_idx, _ in plan]]
    return joints, neutral_ends(joints, ends, carriers, corrections)
