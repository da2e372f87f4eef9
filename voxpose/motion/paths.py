"""Paths and noise shared by the generated and the derived motions (Section 6's spiral and drunken walks).

The heading of a walk along a spiral of shrinking radius (``spiral_heading``, ``spiral_radius``) and the lean into
its turn (``turn_lean``), a wandering heading (``random_walk_heading``) and smooth unit-variance noise
(``smooth_noise``) for drunken walks. ``voxpose.motion.generate`` builds motions on them from scratch,
``voxpose.motion.derive`` puts them on captured straight walks.
"""

import numpy as np
from scipy.ndimage import gaussian_filter1d

from voxpose.errors import VoxposeError

GRAVITY = 9.81  # m/s^2


def smooth_noise(rng: np.random.Generator, n: int, sigma_frames: float) -> np.ndarray:
    """(n,) stationary Gaussian process with unit variance: white noise smoothed by a Gaussian kernel.

    The normalisation is the analytic one (a unit-sum Gaussian kernel of width ``sigma_frames`` leaves a
    variance of 1 / (2 sqrt(pi) sigma)), so the scale does not depend on the length drawn.
    """
    sigma = max(float(sigma_frames), 1.0)
    return gaussian_filter1d(rng.standard_normal(n), sigma, mode="reflect") * np.sqrt(2 * np.sqrt(np.pi) * sigma)


def random_walk_heading(rng: np.random.Generator, n: int, dt: float, rate: float, smooth_s: float = 0.5) -> np.ndarray:
    """(n,) heading wander in degrees: a Gaussian-smoothed random walk starting at 0.

    ``rate`` is the random walk's diffusion in degrees per sqrt(second) (after T seconds its standard
    deviation is ``rate * sqrt(T)``); ``smooth_s`` (seconds) removes frame-to-frame jitter.
    """
    walk = np.cumsum(rng.standard_normal(n) * rate * np.sqrt(dt))
    walk = gaussian_filter1d(walk, max(smooth_s / dt, 1.0), mode="nearest")
    return walk - walk[0]


def spiral_heading(arc_length, *, r_start: float, r_end: float, length: float) -> np.ndarray:
    """Heading change (radians, turning one way) after walking ``arc_length`` along a shrinking spiral.

    The path's radius of curvature falls linearly with arc length s from ``r_start`` at s = 0 to
    ``r_end`` at s = ``length`` and stays ``r_end`` beyond (a circle), so the curvature 1/r grows along
    the path. The heading is the integral of the curvature:
    psi(s) = length / (r_end - r_start) * ln(r(s) / r_start), or s / r_start for a constant radius.
    Arc lengths and radii share one unit; negative arc lengths use the radius ``r_start``.
    """
    if not (r_start > 0 and r_end > 0 and length > 0):
        raise VoxposeError(f"spiral: r_start, r_end and length must be positive, got {r_start}, {r_end}, {length}")
    s = np.asarray(arc_length, dtype=float)
    inside = np.clip(s, 0.0, length)
    if np.isclose(r_start, r_end):
        psi = inside / r_start
    else:
        radius = r_start + (r_end - r_start) * inside / length
        psi = length / (r_end - r_start) * np.log(radius / r_start)
    return psi + (s - inside) / np.where(s > length, r_end, r_start)


def spiral_radius(arc_length, *, r_start: float, r_end: float, length: float) -> np.ndarray:
    """Radius of curvature of the ``spiral_heading`` path at ``arc_length``."""
    s = np.clip(np.asarray(arc_length, dtype=float), 0.0, length)
    return r_start + (r_end - r_start) * s / length


def turn_lean(speed, radius) -> np.ndarray:
    """Lean (radians) into a turn of ``radius`` (m) at ``speed`` (m/s): ``atan(v^2 / (g r))``, the body's
    balance of gravity and the centripetal acceleration."""
    return np.arctan(speed**2 / (GRAVITY * radius))
