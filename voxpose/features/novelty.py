"""A warning for frames far from the training data, from the MPPCA's own density (Section 5).

The MPPCA fitted on the training descriptors is a density model: ``log p(t)`` of a shape context ``t`` is low
where the training bodies and poses never put one. A body or skeleton family far from training (another
height, girth, proportions) moves whole frames there, and the regressor then extrapolates silently. So each
frame gets a *novelty score*, the mean ``log p(t_n)`` of its descriptors, and a motion whose frames score far
below the training frames is logged as out of range.

Choices (documented here, tested in ``tests/features/test_novelty.py``):

- A frame's score averages at most ``DESCRIPTORS_PER_FRAME`` of its descriptors, taken evenly spaced through
  the frame's list (deterministic, no random draw). Scoring costs as much as the Eq. 5 posteriors, so a
  sample keeps it to a small fraction of the feature transformation.
- The training range is measured on at most ``TRAINING_FRAMES`` training frames, evenly spaced through the
  training set, after the fit: ``low`` is their 1st percentile, ``median`` their median.
- The threshold lies as far below ``low`` as ``low`` lies below the median:
  ``threshold = low - (median - low)``. A frame below it is *out of range*; a motion whose median frame is
  below it (at least half its frames out of range) is logged with a warning.
"""

import logging
from dataclasses import asdict, dataclass

import numpy as np

from voxpose.errors import VoxposeError

log = logging.getLogger(__name__)

DESCRIPTORS_PER_FRAME = 20
TRAINING_FRAMES = 500


def evenly_spaced(n: int, k: int) -> np.ndarray:
    """At most ``k`` indices of ``range(n)``, evenly spaced and including the first."""
    if n <= k:
        return np.arange(n)
    return (np.arange(k) * n) // k


def frame_means(log_density, frames: list, per_frame: int) -> np.ndarray:
    """(F,) mean of ``log_density`` (rows (n, bins) -> (n,)) over up to ``per_frame`` of each frame's
    descriptors, evenly spaced through its list; NaN for a frame without descriptors. All frames' picked rows
    go to ``log_density`` at once."""
    picked = [d[evenly_spaced(len(d), per_frame)] for d in frames]
    sizes = np.array([len(d) for d in picked])
    means = np.full(len(frames), np.nan)
    if sizes.sum():
        density = log_density(np.concatenate([d for d in picked if len(d)]))
        present = sizes > 0
        means[present] = np.add.reduceat(density, np.r_[0, np.cumsum(sizes[present])[:-1]]) / sizes[present]
    return means


def frame_scores(mppca, frames: list) -> np.ndarray:
    """(F,) novelty score of each frame: mean ``log p(t)`` of up to ``DESCRIPTORS_PER_FRAME`` of its
    descriptors under ``mppca``; NaN for a frame without descriptors."""
    return frame_means(mppca.score_samples, frames, DESCRIPTORS_PER_FRAME)


@dataclass(frozen=True)
class NoveltyRange:
    """The training frames' score range and the threshold below which a frame is out of range."""

    low: float
    median: float
    threshold: float
    n_frames: int

    @classmethod
    def from_training(cls, mppca, frames: list) -> "NoveltyRange":
        """Measure the range on up to ``TRAINING_FRAMES`` evenly spaced training frames (module docstring)."""
        chosen = [frames[i] for i in evenly_spaced(len(frames), TRAINING_FRAMES)]
        scores = frame_scores(mppca, chosen)
        scores = scores[np.isfinite(scores)]
        if not scores.size:
            raise VoxposeError("novelty range: no training frame has descriptors")
        low, median = np.percentile(scores, [1.0, 50.0])
        return cls(float(low), float(median), float(low - (median - low)), int(scores.size))

    def to_dict(self) -> dict:
        return asdict(self)

    def check(self, motion: str, scores: np.ndarray) -> dict:
        """Summary of one motion's frame ``scores``; logs a warning when its median frame is below the threshold."""
        finite = scores[np.isfinite(scores)]
        if not finite.size:
            return {"median": None, "out_of_range": None, "warned": False}
        median = float(np.median(finite))
        out = float(np.mean(finite < self.threshold))
        warned = median < self.threshold
        if warned:
            log.warning(
                "%s: %.0f %% of its frames lie far outside the training data (median MPPCA log-likelihood %.1f "
                "per descriptor, training median %.1f, threshold %.1f): expect a poor estimate",
                motion, 100 * out, median, self.median, self.threshold,
            )  # fmt: skip
        return {"median": median, "out_of_range": out, "warned": bool(warned)}
