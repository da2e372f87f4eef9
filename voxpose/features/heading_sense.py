"""The body frame's heading sense chosen by the feature model's density (issue 18, item 4; Section 5's MPPCA).

The body frame (``descriptors.body_frame``) reads each hull's facing axis off its trunk and picks one of the
axis's two senses by a shape cue calibrated on the generated body. On real walks that cue points backwards on
22-27 % of the frames, in long stretches, and each such frame costs a heading error of about 180 degrees. The
feature model knows the training bodies better than any hand-made cue: it is a density of their shape contexts
(the MPPCA of Section 5; for the K-means baseline the isotropic mixture its soft vote assumes,
``log p(t) = -min_j |t - c_j|^2 / (2 s^2)`` up to a constant, ``s`` the vote's width). So, with
``features.heading_sense: density`` (the default; ``shape`` keeps the body frame's own choice):

1. before the fit, every training frame whose reference heading points more than 90 degrees away from its true
   heading is turned about (``true_turns``): the model learns bodies seen from the front;
2. every motion, training and test alike (as on new data), gets per frame the *sense evidence*
   ``mean log p(t) - mean log p(turned t)`` over up to ``SENSE_DESCRIPTORS`` of its descriptors, evenly spaced
   through the frame's list; the senses of the sequence are chosen from it by ``body_frame.continuous_headings``
   (a person does not turn about between consecutive frames), and the frames chosen the other way get
   ``h0 + 180`` and turned descriptors (``choose_senses``).

Turning a frame about needs no second description: a shape context's azimuth sectors cover
``[k, k + 1) * 360 / n_a`` degrees about the vertical, so a turn by 180 degrees moves sector ``k`` to
``k + n_a / 2`` (``turn_about``; exact for even ``n_a``, soft votes included, as they wrap in azimuth alike). The
turned frame keeps its basis voxels (turned with it) rather than drawing them again on the turned grid.

Measured offline on the cross-family check's real descriptors (MPPCA K = 200, q = 5, fitted on 20,000 drawn rows
of the truth-turned training frames; 40 descriptors per frame): frames with the wrong sense, body frame's cue
-> density per frame -> density over the sequence: Bandai -> CMU walks 512 -> 4 -> 0 of 2252, CMU -> Bandai
1460 -> 195 -> 10 of 5738. On the embedded default's hulls (Table 1's training set): spiral_gen_03 0 -> 0 -> 0 of
418; every ``_gen_02`` and ``_gen_03`` motion 1 -> 5 -> 5 of 1828 (all five in jump_gen_02).
"""

import logging

import numpy as np

from voxpose.descriptors.body_frame import continuous_headings
from voxpose.errors import VoxposeError
from voxpose.features.novelty import frame_means

log = logging.getLogger(__name__)

SENSES = ("density", "shape")

SENSE_DESCRIPTORS = 40
"""Descriptors per frame (evenly spaced through its list) whose densities weigh the two senses: 20 gave 12
wrong per-frame senses where 40 gave 4 on the Bandai -> CMU walks (0 for both over the sequence)."""


def wrapped(degrees) -> np.ndarray:
    """Angles wrapped into [-180, 180)."""
    return np.mod(np.asarray(degrees, dtype=float) + 180.0, 360.0) - 180.0


def turn_about(descriptors: np.ndarray, n_a: int) -> np.ndarray:
    """Shape contexts (B, n_r * n_e * n_a) of a body turned by 180 degrees about the vertical: every ring's
    azimuth sectors shifted by ``n_a / 2`` (the flat index is ``(i_r * n_e + i_e) * n_a + i_a``)."""
    if n_a % 2:
        raise VoxposeError(f"descriptor: n_a = {n_a} is odd; heading_sense: density needs an even number of "
                           "azimuth sectors (or features.heading_sense: shape)")  # fmt: skip
    d = np.asarray(descriptors)
    return np.roll(d.reshape(len(d), -1, n_a), n_a // 2, axis=-1).reshape(d.shape)


def true_turns(h0, true_heading) -> np.ndarray:
    """(F,) bool: frames whose reference heading ``h0`` points more than 90 degrees from the true heading."""
    return np.abs(wrapped(np.asarray(true_heading) - np.asarray(h0))) > 90.0


def turned_frames(frames: list, turns, n_a: int) -> list:
    """``frames`` (each (B_f, bins)) with the ones where ``turns`` is true turned about."""
    return [turn_about(d, n_a) if t and len(d) else d for d, t in zip(frames, turns, strict=True)]


def sense_evidence(log_density, frames: list, n_a: int, as_is=None) -> np.ndarray:
    """(F,) mean ``log p(t)`` of a frame's descriptors minus that of them turned about (module docstring),
    positive where the frame looks more like a training body as it stands; 0 for frames without descriptors.
    ``log_density`` maps rows (n, bins) to (n,) log densities; ``as_is``, the first term when the caller has
    it already (``frame_means`` of the frames' own log densities)."""
    if as_is is None:
        as_is = frame_means(log_density, frames, SENSE_DESCRIPTORS)
    turned = frame_means(lambda rows: log_density(turn_about(rows, n_a)), frames, SENSE_DESCRIPTORS)
    empty = np.array([len(d) == 0 for d in frames], dtype=bool)
    return np.where(empty, 0.0, as_is - turned)


def choose_senses(log_density, frames: list, h0, n_a: int, name: str = "motion", as_is=None) -> tuple[list, np.ndarray]:
    """``(frames, h0)`` of a sequence with each frame's sense chosen by the density (module docstring): frames
    turned about where the chosen reference heading differs from ``h0`` by 180 degrees. ``as_is``: as in
    ``sense_evidence``."""
    h0 = np.asarray(h0, dtype=float)
    evidence = sense_evidence(log_density, frames, n_a, as_is)
    carved = np.flatnonzero([len(d) > 0 for d in frames])
    chosen = h0.copy()
    chosen[carved] = continuous_headings(h0[carved], evidence[carved], carved)
    turns = true_turns(h0, chosen)
    log.info("heading sense %s: %d of %d frames turned about by the feature model's density", name,
             int(turns.sum()), len(carved))  # fmt: skip
    return turned_frames(frames, turns, n_a), np.mod(chosen, 360.0)
