"""Paths and noise of the generated and derived motions against closed forms and their statistics."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.motion.paths import GRAVITY, random_walk_heading, smooth_noise, spiral_heading, spiral_radius, turn_lean


def test_spiral_heading_is_the_integral_of_the_curvature():
    geometry = dict(r_start=4.0, r_end=1.0, length=10.0)
    s = np.linspace(-1.0, 14.0, 30001)
    psi = spiral_heading(s, **geometry)
    assert psi[np.searchsorted(s, 0.0)] == pytest.approx(0.0, abs=1e-3)
    curvature = np.gradient(psi, s)
    expected = 1.0 / spiral_radius(s, **geometry)
    inner = (np.abs(s) > 0.01) & (np.abs(s - 10.0) > 0.01)
    np.testing.assert_allclose(curvature[inner], expected[inner], rtol=1e-5)
    assert spiral_radius(12.0, **geometry) == 1.0 and spiral_radius(-1.0, **geometry) == 4.0
    np.testing.assert_allclose(spiral_heading(s, r_start=2.0, r_end=2.0, length=5.0), s / 2.0)
    with pytest.raises(VoxposeError, match="positive"):
        spiral_heading(s, r_start=0.0, r_end=1.0, length=1.0)


def test_random_walk_heading_diffuses_at_its_rate():
    rng = np.random.default_rng(0)
    dt, n = 1 / 30, 301
    ends = np.array([random_walk_heading(rng, n, dt, rate=20.0, smooth_s=0.2)[-1] for _ in range(400)])
    # starts at 0; after 10 s the spread is 20 * sqrt(10) degrees (a little less: the smoothing at the end)
    assert np.std(ends) == pytest.approx(20.0 * np.sqrt(10.0), rel=0.15)
    assert random_walk_heading(rng, n, dt, rate=20.0)[0] == 0.0


def test_smooth_noise_has_unit_variance_whatever_its_width():
    rng = np.random.default_rng(1)
    for sigma in (3.0, 15.0):
        x = smooth_noise(rng, 200_000, sigma)
        assert np.var(x) == pytest.approx(1.0, rel=0.05)
        lag = int(sigma)
        assert np.corrcoef(x[:-lag], x[lag:])[0, 1] == pytest.approx(np.exp(-(lag**2) / (4 * sigma**2)), abs=0.03)


def test_turn_lean_balances_gravity_and_the_centripetal_acceleration():
    # v^2 / r = g: 45 degrees; no speed or an infinite radius: upright; the lean grows with the speed
    assert turn_lean(np.sqrt(GRAVITY * 2.0), 2.0) == pytest.approx(np.pi / 4)
    assert turn_lean(0.0, 1.5) == 0.0 and turn_lean(1.4, np.inf) == 0.0
    lean = turn_lean(np.array([0.5, 1.0, 2.0]), 3.0)
    np.testing.assert_allclose(np.tan(lean) * GRAVITY * 3.0, [0.25, 1.0, 4.0])
