"""95 % bootstrap intervals of the tables' errors and paired comparisons of two methods (Section 6, issue 20).

The tables' errors (``voxpose.evaluation.metrics``) are the mean over angles of each angle's RMS over the test
frames. Their uncertainty comes from which motions and frames were tested, so the bootstrap resamples the test
set hierarchically: the test motions with replacement, then the frames of each drawn motion with replacement.
A replicate is a weight per frame (how often it was drawn), and each angle's RMS is
``sqrt(sum_f w_f d_fa^2 / sum_f w_f)``; the interval is the 2.5 and 97.5 percentiles over replicates.
Frames of one motion are correlated in time, so with one test motion (Table 1) the interval is narrower
than a new take of that motion would show; the caption says so.

A paired comparison applies the same replicates to two methods' differences on the same frames: the
interval of the difference of their errors, and a two-sided bootstrap p-value (twice the smaller tail of the
replicated difference beyond zero). Beside it, a Wilcoxon signed-rank test on the per-frame Eq. 6 errors.

Varying angles: an angle whose true value has a standard deviation over the test frames of at most
``STILL_DEG`` does not move in the test data; a regressor trained where it also stays still predicts it exactly,
a free zero in the mean over 42 angles. The tables give the error over the varying angles beside it.
"""

from dataclasses import dataclass

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.io.hdf5 import read_per_motion
from voxpose.motion import canon
from voxpose.motion.data import kind_of

STILL_DEG = 0.1  # standard deviation (degrees) over the test frames at or below which an angle is still
_HEADING = canon.ANGLE_NAMES.index("root_y")
# Table 1's columns as angle selections (each joint: the mean of its three angles).
COLUMNS = {
    "heading": [_HEADING],
    "left_shoulder": [3 * canon.INDEX["lshoulder"] + i for i in range(3)],
    "right_hip": [3 * canon.INDEX["rhip"] + i for i in range(3)],
}


@dataclass
class FrameErrors:
    """One method's test frames: per motion, the true angles and the wrapped differences (F, 42), and its type."""

    motions: list[str]
    kinds: list[str]
    true: list[np.ndarray]
    diff: list[np.ndarray]

    def restrict(self, keep: list[np.ndarray]) -> "FrameErrors":
        """The same motions with only the frames ``keep[i]`` (boolean) of motion i."""
        return FrameErrors(
            self.motions,
            self.kinds,
            [t[k] for t, k in zip(self.true, keep, strict=True)],
            [d[k] for d, k in zip(self.diff, keep, strict=True)],
        )

    def of_kind(self, kind: str) -> "FrameErrors":
        idx = [i for i, k in enumerate(self.kinds) if k == kind]
        return FrameErrors(*([getattr(self, f)[i] for i in idx] for f in ("motions", "kinds", "true", "diff")))


def _wrapped(a, b) -> np.ndarray:
    d = np.mod(a - b, 360.0)
    return np.minimum(d, 360.0 - d)


def read_test_frames(path, method: str = "mvrvm", valid: dict | None = None) -> FrameErrors:
    """``method``'s valid test frames from an evaluation's ``predictions.h5`` (``voxpose evaluate``).

    ``valid``: motion -> boolean mask; when given, only frames valid there too (two runs compared frame by frame).
    """
    motions, _ = read_per_motion(path, "predictions")
    out = FrameErrors([], [], [], [])
    for name in sorted(motions):
        arrays = motions[name]
        if f"pred_{method}" not in arrays:
            raise VoxposeError(f"{path}: no predictions of method {method!r} for motion {name!r}")
        keep = arrays["valid"].astype(bool) & (valid[name] if valid is not None else True)
        out.motions.append(name)
        out.kinds.append(kind_of(name))
        out.true.append(arrays["true"][keep])
        out.diff.append(_wrapped(arrays["true"][keep], arrays[f"pred_{method}"][keep]))
    return out


def valid_masks(path) -> dict:
    """motion -> the frames with a prediction in ``predictions.h5``."""
    motions, _ = read_per_motion(path, "predictions")
    return {name: arrays["valid"].astype(bool) for name, arrays in motions.items()}


def varying(frames: FrameErrors) -> np.ndarray:
    """(42,) True for the angles whose true value moves over the test frames (std above ``STILL_DEG``)."""
    true = np.concatenate(frames.true)
    centred = np.rad2deg(np.angle(np.exp(1j * np.deg2rad(true - true[:1]))))  # wrap-safe spread
    return centred.std(axis=0) > STILL_DEG


def replicate_weights(frames: FrameErrors, n: int, seed: int) -> np.ndarray:
    """(n, F) frame weights of ``n`` hierarchical bootstrap replicates (motions, then frames); row 0 is all ones
    (the estimate itself is not a replicate and is not used for the interval)."""
    rng = np.random.default_rng(seed)
    sizes = np.array([len(d) for d in frames.diff])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    weights = np.zeros((n, int(sizes.sum())))
    for b in range(n):
        for m in rng.integers(0, len(sizes), len(sizes)):
            np.add.at(weights[b], starts[m] + rng.integers(0, sizes[m], sizes[m]), 1.0)
    return weights


def _errors(weights: np.ndarray, diff: np.ndarray, angles) -> np.ndarray:
    """Per replicate, the mean over ``angles`` of each angle's weighted RMS over frames."""
    sq = weights @ (diff[:, angles] ** 2) / weights.sum(axis=1, keepdims=True)
    return np.sqrt(sq).mean(axis=1)


def estimate(frames: FrameErrors, angles, n: int, seed: int) -> tuple[float, float, float]:
    """(error, 2.5 %, 97.5 %) over ``angles`` (indices or a boolean mask of the 42)."""
    diff = np.concatenate(frames.diff)
    if len(diff) == 0:
        return (float("nan"),) * 3
    value = float(np.sqrt(np.mean(diff[:, angles] ** 2, axis=0)).mean())
    lo, hi = np.percentile(_errors(replicate_weights(frames, n, seed), diff, angles), [2.5, 97.5])
    return value, float(lo), float(hi)


@dataclass(frozen=True)
class Comparison:
    """``a`` against ``b`` on the same frames: their errors, the difference a - b with its interval, p-values."""

    a: float
    b: float
    difference: float
    low: float
    high: float
    p_bootstrap: float
    p_wilcoxon: float
    frames: int

    @property
    def verdict(self) -> str:
        """``held`` when a is lower with the whole interval below zero, ``reversed`` when the interval is above
        zero, else ``not shown`` (the data cannot tell the two apart)."""
        return "held" if self.high < 0 else "reversed" if self.low > 0 else "not shown"


def compare(a: FrameErrors, b: FrameErrors, angles, n: int, seed: int) -> Comparison:
    """Paired comparison of two methods' errors over ``angles`` on the same test frames."""
    da, db = np.concatenate(a.diff), np.concatenate(b.diff)
    if da.shape != db.shape:
        raise VoxposeError(f"paired comparison: {len(da)} and {len(db)} test frames differ")
    weights = replicate_weights(a, n, seed)
    ea, eb = (float(np.sqrt(np.mean(d[:, angles] ** 2, axis=0)).mean()) for d in (da, db))
    rep = _errors(weights, da, angles) - _errors(weights, db, angles)
    lo, hi = np.percentile(rep, [2.5, 97.5])
    p_boot = min(1.0, 2 * min(np.mean(rep >= 0), np.mean(rep <= 0)))
    fa, fb = da[:, angles].mean(axis=1), db[:, angles].mean(axis=1)
    from scipy.stats import wilcoxon  # here, not at the top: scipy.stats costs 0.5 s to import in every evaluate job

    p_wil = float(wilcoxon(fa, fb).pvalue) if np.any(fa != fb) else 1.0
    return Comparison(ea, eb, ea - eb, float(lo), float(hi), float(p_boot), p_wil, len(da))
