"""Bootstrap intervals and paired comparisons against planted errors and brute-force resampling."""

import numpy as np
import pytest

from voxpose.evaluation import metrics
from voxpose.evaluation.uncertainty import FrameErrors, _errors, compare, estimate, replicate_weights, varying

ALL = np.arange(42)


def frames_of(*diffs, true=None) -> FrameErrors:
    true = true or [np.zeros_like(d) for d in diffs]
    return FrameErrors([f"walk_{i}" for i in range(len(diffs))], ["walk"] * len(diffs), list(true), list(diffs))


def test_estimate_is_the_tables_full_body_error_and_lies_in_its_interval():
    rng = np.random.default_rng(0)
    diffs = [rng.uniform(0, 20, (30, 42)), rng.uniform(0, 5, (50, 42))]
    value, lo, hi = estimate(frames_of(*diffs), ALL, 300, 1)
    assert value == pytest.approx(metrics.full_body_error(np.concatenate(diffs), np.zeros((80, 42))))
    assert lo < value < hi


def test_weighted_replicate_equals_the_error_of_the_resampled_frames():
    rng = np.random.default_rng(1)
    diff = rng.uniform(0, 10, (40, 42))
    idx = rng.integers(0, 40, 40)  # one replicate drawn by hand
    weights = np.bincount(idx, minlength=40)[None].astype(float)
    assert _errors(weights, diff, ALL)[0] == pytest.approx(metrics.full_body_error(diff[idx], np.zeros((40, 42))))


def test_motions_are_resampled_before_frames():
    # two motions with constant errors 1 and 3: frames alone cannot vary the error, drawing motions can
    frames = frames_of(np.full((20, 42), 1.0), np.full((20, 42), 3.0))
    _, lo, hi = estimate(frames, ALL, 400, 2)
    assert lo == pytest.approx(1.0) and hi == pytest.approx(3.0)
    one = frames_of(np.full((20, 42), 2.0))
    assert estimate(one, ALL, 50, 2)[1:] == pytest.approx((2.0, 2.0))


def test_weights_are_seeded_and_count_whole_motions():
    frames = frames_of(np.ones((5, 42)), np.ones((5, 42)))
    w = replicate_weights(frames, 20, 3)
    assert np.array_equal(w, replicate_weights(frames, 20, 3)) and not np.array_equal(
        w, replicate_weights(frames, 20, 4)
    )
    assert np.all(w.sum(axis=1) == 10)  # two motions of five frames drawn per replicate


def test_paired_comparison_verdicts():
    rng = np.random.default_rng(5)
    base = rng.uniform(2, 6, (60, 42))
    better = frames_of(base[:30] * 0.5, base[30:] * 0.5)
    worse = frames_of(base[:30], base[30:])
    held = compare(better, worse, ALL, 300, 0)
    assert held.verdict == "held" and held.high < 0 and held.p_wilcoxon < 1e-6 and held.frames == 60
    assert held.difference == pytest.approx(held.a - held.b)
    assert compare(worse, better, ALL, 300, 0).verdict == "reversed"
    same = compare(worse, worse, ALL, 300, 0)
    assert same.verdict == "not shown" and same.difference == 0 and same.p_wilcoxon == 1.0


def test_still_angles_are_not_varying():
    rng = np.random.default_rng(6)
    true = rng.normal(0, 10, (50, 42))
    true[:, 12:15] = 7.0  # a wrist that never moves
    true[:, 0] = 179.99 + np.where(np.arange(50) % 2, 0.0, 0.02)  # heading across +-180: still, once wrapped
    true[:, 0] = np.where(true[:, 0] > 180, true[:, 0] - 360, true[:, 0])
    mask = varying(frames_of(np.zeros((50, 42)), true=[true]))
    assert list(np.flatnonzero(~mask)) == [0, 12, 13, 14]
