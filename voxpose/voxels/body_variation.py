"""Body variation (issue 18 item 3): each motion's body drawn with its own girths and segment lengths.

A skeleton family gives every one of its motions nearly the same proportions (the Bandai files share one rig,
the generated skeleton is one table scaled by height), so a regressor trained on one family sees one body.
With ``voxels.variation`` set, every motion's body gets factors drawn from log-normal distributions
(``exp(N(0, sd^2))``, median 1):

* ``girth_sd``: the widths and depths of the solids, one factor each for the trunk (pelvis, abdomen, chest),
  the arms (upper arms, forearms, hands) and the legs (thighs, shins, feet); the head is kept.
* ``length_sd``: one factor each for the trunk (pelvis centre -> base of the neck), upper arm, forearm, thigh
  and shin, the same on both sides. A segment is scaled about its proximal landmark and everything distal to
  it moves with its far end (``vary_lengths``); the body is then raised by the change of the median standing
  leg length so the feet stay on the floor.

The defaults are 0 (off). The sds are the config's choice, one for girths and one for lengths, as adults
differ by different amounts in the two (measured with girth_sd 0.10 and length_sd 0.05 in issue 18). The
stature that results is measured from the hull like any subject's (``h_sub``, Section 4), and the angles,
the regression targets, are untouched: only the picture of the body changes.

Draws depend only on the config's seed and the motion's name (``numpy.random.default_rng([seed, crc32(name)])``),
so a motion's body does not change when other motions join or leave the run and cached voxels stay valid.
"""

import zlib
from dataclasses import dataclass

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.motion import canon

GIRTH_GROUPS = {
    "trunk": ("pelvis", "abdomen", "chest"),
    "arms": ("lupperarm", "lforearm", "lhand", "rupperarm", "rforearm", "rhand"),
    "legs": ("lthigh", "lshin", "lfoot", "rthigh", "rshin", "rfoot"),
}
LENGTHS = ("trunk", "upperarm", "forearm", "thigh", "shin")

_I = canon.INDEX
_E = {name: i for i, name in enumerate(canon.ENDS)}
# segment: [(proximal joint, distal joint, joints and ends that move with the distal joint)] per side
_CHAINS = {
    "trunk": [("root", "neck", ["neck", "lshoulder", "lelbow", "lwrist", "rshoulder", "relbow", "rwrist"],
               ["head_top", "lhand_tip", "rhand_tip"])],
    "upperarm": [(s + "shoulder", s + "elbow", [s + "elbow", s + "wrist"], [s + "hand_tip"]) for s in "lr"],
    "forearm": [(s + "elbow", s + "wrist", [s + "wrist"], [s + "hand_tip"]) for s in "lr"],
    "thigh": [(s + "hip", s + "knee", [s + "knee", s + "ankle"], [s + "toe"]) for s in "lr"],
    "shin": [(s + "knee", s + "ankle", [s + "ankle"], [s + "toe"]) for s in "lr"],
}  # fmt: skip


@dataclass(frozen=True)
class BodyVariation:
    """The config's ``voxels.variation``: log-normal sds of the girth and length factors (0: off)."""

    girth_sd: float = 0.0
    length_sd: float = 0.0

    def __post_init__(self):
        for key in ("girth_sd", "length_sd"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, int | float) or not 0 <= value <= 0.5:
                raise VoxposeError(f"voxels.variation.{key} must be a number in [0, 0.5], got {value!r}")

    @property
    def active(self) -> bool:
        return self.girth_sd > 0 or self.length_sd > 0

    def draw(self, motion_name: str, seed: int) -> dict | None:
        """``{"girth": {group: f}, "length": {segment: f}}`` for one motion, or None when off."""
        if not self.active:
            return None
        rng = np.random.default_rng([int(seed), zlib.crc32(motion_name.encode())])
        girth = np.exp(self.girth_sd * rng.standard_normal(len(GIRTH_GROUPS)))
        length = np.exp(self.length_sd * rng.standard_normal(len(LENGTHS)))
        return {
            "girth": dict(zip(GIRTH_GROUPS, girth.tolist(), strict=True)),
            "length": dict(zip(LENGTHS, length.tolist(), strict=True)),
        }


def vary_girths(table: dict, girth: dict) -> dict:
    """A copy of a proportions table with each group's widths and depths multiplied by its factor."""
    out = {name: dict(sizes) for name, sizes in table.items()}
    for group, factor in girth.items():
        for name in GIRTH_GROUPS[group]:
            for key in ("width", "depth"):
                out[name][key] *= factor
    return out


def vary_lengths(joints: np.ndarray, ends: np.ndarray, length: dict):
    """Landmark joints (F, 14, 3) and ends (F, 5, 3) with the segments scaled (module docstring)."""
    joints, ends = joints.copy(), ends.copy()
    for segment in LENGTHS:
        factor = length[segment]
        for near, far, joint_names, end_names in _CHAINS[segment]:
            shift = (factor - 1.0) * (joints[:, _I[far]] - joints[:, _I[near]])
            joints[:, [_I[n] for n in joint_names]] += shift[:, None]
            ends[:, [_E[n] for n in end_names]] += shift[:, None]
    legs = []
    for side in "lr":
        thigh = np.linalg.norm(joints[:, _I[side + "knee"]] - joints[:, _I[side + "hip"]], axis=-1)
        shin = np.linalg.norm(joints[:, _I[side + "ankle"]] - joints[:, _I[side + "knee"]], axis=-1)
        legs.append(np.median(thigh) * (1 - 1 / length["thigh"]) + np.median(shin) * (1 - 1 / length["shin"]))
    raise_by = np.array([0.0, float(np.mean(legs)), 0.0])
    return joints + raise_by, ends + raise_by
