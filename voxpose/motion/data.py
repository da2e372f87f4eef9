"""``MotionData``: one motion on the canonical body (see ``voxpose.motion.canon``), what every later stage reads,
and its file layout (``motions/{motion}.h5``)."""

from dataclasses import dataclass, field

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path
from voxpose.io.hdf5 import new_file, open_layout, read_meta, write_meta


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
    ends : (F, 5, 3) end points ``motion.canon.ENDS`` in metres (head top, hand tips, toes).
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


# --- motions/{motion}.h5: canonical poses (Section 2) -------------------------------------------------------


def write_motion(path, motion: MotionData) -> None:
    """One motion's canonical poses, joint positions, end points and skeleton offsets (at least one frame)."""
    if motion.n_frames < 1:
        raise VoxposeError(f"write_motion {path}: motion {motion.name!r} has no frames")
    with atomic_path(path) as tmp, new_file(tmp, "motion") as f:
        for key in ("positions", "rotations", "angles", "ends"):
            f.create_dataset(key, data=getattr(motion, key), compression="gzip", chunks=True)
        f.create_dataset("offsets", data=motion.offsets)
        meta = {"name": motion.name, "kind": motion.kind, "fps": motion.fps, "height": motion.height}
        write_meta(f, meta | {"source": motion.source})


def read_motion(path) -> MotionData:
    """A motion file; one without frames (no stage can use it) is refused naming the file."""
    with open_layout(path, "motion") as f:
        meta = read_meta(f)
        if f["positions"].shape[0] < 1:
            raise VoxposeError(f"{path}: the motion file has no frames")
        return MotionData(
            name=meta["name"],
            kind=meta["kind"],
            fps=float(meta["fps"]),
            positions=f["positions"][()],
            rotations=f["rotations"][()],
            angles=f["angles"][()],
            ends=f["ends"][()],
            offsets=f["offsets"][()],
            height=float(meta["height"]),
            source=meta["source"],
        )
