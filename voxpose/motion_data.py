"""``MotionData``: one motion on the canonical body (see ``voxpose.canon``), what every later stage reads."""

from dataclasses import dataclass, field

import numpy as np


def kind_of(motion: str) -> str:
    """A motion's type: its name's prefix before the first ``_`` (walk, jog, spiral, ...)."""
    return motion.split("_", 1)[0]


@dataclass
class MotionData:
    """A motion mapped onto the 14 canonical joints.

    Attributes
    ----------
    name : file stem of the source BVH (``walk_cmu_07_01``); ``kind`` is its prefix (``walk``).
    fps : frame rate after resampling.
    positions : (F, 14, 3) world joint positions in metres, Y up.
    rotations : (F, 14, 3, 3) canonical world rotations (identity in the T-pose facing +Z).
    angles : (F, 42) the pose vector y' in degrees (``canon`` Euler convention), unwrapped over time.
    ends : (F, 5, 3) end points ``canon.ENDS`` in metres (head top, hand tips, toes).
    offsets : (14, 3) each joint's offset from its canonical parent, in the parent's canonical frame
        (metres; the root's row is zero): the subject's skeleton for forward kinematics of y'.
    height : standing height in metres (from the skeleton's rest bone lengths).
    source : free-form provenance (file path, unit scale and how it was chosen, dropped frames).
    """

    name: str
    kind: str
    fps: float
    positions: np.ndarray
    rotations: np.ndarray
    angles: np.ndarray
    ends: np.ndarray
    offsets: np.ndarray
    height: float
    source: dict = field(default_factory=dict)

    @property
    def n_frames(self) -> int:
        return int(self.positions.shape[0])
