"""The shared-alpha step of the MVRVM (Section 3) against dense searches over alpha and Tipping & Faul's
single-output optimum."""

import numpy as np
import pytest

from voxpose.regression import mvrvm_alpha
from voxpose.regression.mvrvm_alpha import optimal_alpha


def grid_max(s, q2):
    """Largest l on a dense grid of log alpha, refined once around the best grid point."""
    grid = np.exp(np.linspace(-30, 30, 12001))
    values = mvrvm_alpha.contribution(grid[:, None], s[None, :], q2[None, :])
    best = int(np.argmax(values))
    fine = np.exp(np.linspace(np.log(grid[max(best - 1, 0)]), np.log(grid[min(best + 1, grid.size - 1)]), 2001))
    return max(values.max(), mvrvm_alpha.contribution(fine[:, None], s[None, :], q2[None, :]).max(), 0.0)


@pytest.mark.parametrize("p", [1, 2, 3, 8])
def test_optimal_alpha_beats_a_dense_grid(p):
    rng = np.random.default_rng(p)
    s = np.exp(rng.normal(0, 1.5, size=(25, p)))
    q2 = s * np.exp(rng.normal(0.3, 1.2, size=(25, p)))
    alpha, value = optimal_alpha(s, q2)
    for i in range(25):
        best = grid_max(s[i], q2[i])
        assert value[i] >= best - 1e-7 * max(1.0, best)
        expected = 0.0 if np.isinf(alpha[i]) else mvrvm_alpha.contribution(alpha[i], s[i], q2[i])
        assert value[i] == pytest.approx(expected, rel=1e-12, abs=1e-12)


def test_optimal_alpha_single_output_is_tipping_faul():
    s = np.array([[2.0], [2.0], [1.0]])
    q2 = np.array([[6.0], [1.0], [1.0]])
    alpha, _ = optimal_alpha(s, q2)
    assert alpha[0] == pytest.approx(4.0 / 4.0)  # s^2 / (q^2 - s)
    assert np.isinf(alpha[1]) and np.isinf(alpha[2])  # q^2 <= s: leave out


def test_optimal_alpha_finds_the_better_of_two_maxima():
    # two outputs wanting very different alphas: l has two local maxima, the higher one must be found
    s = np.array([[1.0, 1.0]])
    q2 = np.array([[1e4, 3.0]])
    alpha, value = optimal_alpha(s, q2)
    assert value[0] == pytest.approx(grid_max(s[0], q2[0]), rel=1e-9)


@pytest.mark.parametrize("subdivisions", [1, 2, 4, 8])
def test_bounds_enclose_the_maximum(subdivisions):
    """Upper bounds above the dense-grid maximum, feasible values below it and equal to l where they are; a
    finer grid never loosens the bound and here tightens it on average."""
    rng = np.random.default_rng(5)
    s = np.exp(rng.normal(0, 1, size=(100, 4))) * np.exp(rng.normal(0, 2, size=(100, 1)))
    q2 = s * np.exp(rng.normal(-0.3, 1.0, size=(100, 4)))
    best = np.array([grid_max(a, b) for a, b in zip(s, q2, strict=True)])
    mode_value, mode_alpha, upper = mvrvm_alpha.mode_bounds(s, q2, subdivisions)
    assert np.all(upper >= best - 1e-9)
    assert np.all(mvrvm_alpha.series_bound(s, q2) >= best - 1e-9)
    finite = np.isfinite(mode_alpha)
    assert np.all(mode_value[finite] <= best[finite] + 1e-12)
    assert np.allclose(mode_value[finite], mvrvm_alpha.contribution(mode_alpha[finite], s[finite], q2[finite]))
    coarse_value, _, coarse_upper = mvrvm_alpha.mode_bounds(s, q2)
    assert np.all(upper <= coarse_upper + 1e-12) and np.all(mode_value >= coarse_value)
    if subdivisions > 1:
        assert np.mean(upper - best) < np.mean(coarse_upper - best)


def test_newton_ascent_reaches_a_local_maximum():
    rng = np.random.default_rng(6)
    s = np.exp(rng.normal(0, 1, size=(50, 3)))
    q2 = s * np.exp(rng.normal(0.5, 1.0, size=(50, 3)))
    start = np.exp(rng.normal(0, 2, size=50))
    alpha, value = mvrvm_alpha.newton_ascent(start, s, q2, steps=60)
    two_alpha, two_value = mvrvm_alpha.newton_ascent(start, s, q2, steps=2)
    assert np.all(two_value >= mvrvm_alpha.contribution(start, s, q2)) and np.all(value >= two_value)
    assert np.all(value >= mvrvm_alpha.contribution(start, s, q2))
    finite = np.isfinite(alpha)
    slope, curvature = mvrvm_alpha.slope_terms(alpha[finite], s[finite], q2[finite])
    assert np.allclose(slope, 0.0, atol=1e-6)
    assert np.all(curvature < 0)
