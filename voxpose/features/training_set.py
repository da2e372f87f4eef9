"""The training descriptors a feature model is fitted on, read one file at a time (Section 5).

The fit needs ``fit_subsample`` rows drawn from every training descriptor, and the novelty range
(``features.novelty``) up to ``TRAINING_FRAMES`` whole frames spread over the training set. Neither needs the
whole set in memory: on the real Table 1 training set (about 1.9 million descriptors of 200 bins) that was
3 GB in float64, twice over while concatenated, and ``fit-features`` peaked at 6.7 GB. ``read_training_set``
counts the rows from the files' offsets, draws the row indices exactly as ``model.subsample`` does on the
concatenated set (they depend on the row count and the seed alone), then reads each file once, keeping only
the drawn rows and the chosen frames: the same numbers, with one file and the drawn rows in memory. A file's
descriptors stay float32 as stored, and only the kept ones are turned and made float64 (the same values: both
steps are exact). Converting and joining every file's rows first: the largest real-data fit took 11.1 s of user
CPU and 596 MB, against 9.8 s and 493 MB now (``/usr/bin/time -v``, its workflow command, one run each).

With ``turns`` (per file, the frames to turn about; ``features.heading_sense``) those frames' descriptors are
turned by 180 degrees about the vertical as they are read, so the model learns bodies seen from the front.
"""

from dataclasses import dataclass

import h5py
import numpy as np

from voxpose.descriptors.file import descriptor_headings, read_descriptor_file
from voxpose.errors import VoxposeError
from voxpose.features.heading_sense import true_turns, turn_about, turned_frames
from voxpose.features.model import subsample_indices
from voxpose.features.novelty import TRAINING_FRAMES, evenly_spaced
from voxpose.motion import canon
from voxpose.motion.data import read_motion


@dataclass(frozen=True)
class TrainingSet:
    """rows: the drawn descriptors (float64, in set order); n_rows: descriptors in the whole set; frames: the
    novelty range's frames ((B_f, bins) float64, evenly spaced over all ``n_frames`` frames)."""

    rows: np.ndarray
    n_rows: int
    frames: list
    n_frames: int


def _sizes(path) -> np.ndarray:
    """Descriptors per frame of a descriptor file, from its offsets alone (its content is checked when read)."""
    with h5py.File(path, "r") as f:
        return np.diff(f["descriptors_offsets"][()])


def _drawn_rows(frames: list, rows: np.ndarray, turn: np.ndarray, n_a: int) -> np.ndarray:
    """Rows ``rows`` (indices into ``frames`` concatenated) as float64, turned about where ``turn`` names their
    frame: what indexing the concatenated, turned, float64 frames gives, without making them."""
    starts = np.cumsum([0] + [len(d) for d in frames])
    frame = np.searchsorted(starts, rows, side="right") - 1
    picked = np.stack([frames[f][r - starts[f]] for f, r in zip(frame, rows, strict=True)]).astype(np.float64)
    turned = turn[frame]
    if turned.any():
        picked[turned] = turn_about(picked[turned], n_a)
    return picked


def read_training_set(paths, n: int | None, seed: int, n_frames: int = TRAINING_FRAMES, turns=None,
                      n_a: int = 0) -> TrainingSet:  # fmt: skip
    """The drawn rows (``n`` of them, all when ``n`` is None or larger than the set) and ``n_frames`` evenly
    spaced frames of the descriptor files ``paths`` taken together in order (module docstring); ``turns``
    (None, or per file an (F,) bool array) names frames to turn about, ``n_a`` the descriptors' azimuth sectors."""
    sizes = [_sizes(path) for path in paths]
    frame_start = np.cumsum([0] + [len(s) for s in sizes])
    row_start = np.cumsum([0] + [int(s.sum()) for s in sizes])
    drawn = subsample_indices(int(row_start[-1]), n, seed)
    chosen = evenly_spaced(int(frame_start[-1]), n_frames)
    rows, frames = [], []
    for k, path in enumerate(paths):
        lo, hi = np.searchsorted(drawn, row_start[k : k + 2])
        pick_lo, pick_hi = np.searchsorted(chosen, frame_start[k : k + 2])
        stored = read_descriptor_file(path, dtype=None).frames  # each file read whole (its checksum checked), once
        turn = np.zeros(len(stored), dtype=bool) if turns is None else np.asarray(turns[k], dtype=bool)
        if lo < hi:
            rows.append(_drawn_rows(stored, drawn[lo:hi] - row_start[k], turn, n_a))
        picked = chosen[pick_lo:pick_hi] - frame_start[k]
        frames.extend(d.astype(np.float64) for d in turned_frames([stored[i] for i in picked], turn[picked], n_a))
    width = rows[0].shape[1] if rows else 0
    return TrainingSet(np.concatenate(rows) if rows else np.zeros((0, width)), int(row_start[-1]), frames,
                       int(frame_start[-1]))  # fmt: skip


def training_turns(descriptor_paths, motion_paths) -> tuple[list | None, int]:
    """``(turns, n_a)`` for ``read_training_set``: per descriptor file, the frames whose body-frame reference
    heading points more than 90 degrees from the true heading of its motion file (same order), and the files'
    azimuth sectors; ``(None, 0)`` for world-frame descriptors. A missing or mismatched motion file is a
    one-line error naming both files."""
    if len(motion_paths) != len(descriptor_paths):
        raise VoxposeError(f"fit-features: {len(motion_paths)} motion files for {len(descriptor_paths)} descriptor "
                           "files; --motions takes the training motions' files in the descriptors' order")  # fmt: skip
    turns, n_a = [], 0
    for d_path, m_path in zip(descriptor_paths, motion_paths, strict=True):
        h0, meta = descriptor_headings(d_path)  # each file's checksum is checked when read_training_set reads it
        if h0 is None:
            return None, 0
        motion = read_motion(m_path)
        if motion.name != meta["motion"] or motion.n_frames != len(h0):
            raise VoxposeError(f"{m_path}: motion {motion.name!r} ({motion.n_frames} frames) does not match the "
                               f"descriptors {d_path} ({meta['motion']!r}, {len(h0)} frames)")  # fmt: skip
        turns.append(true_turns(h0, motion.angles[:, canon.ANGLE_NAMES.index("root_y")]))
        n_a = int(meta["params"]["n_a"])
    return turns, n_a
