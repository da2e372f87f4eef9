"""How y' is presented to the regressor: the body heading as a circle, every other angle as it is.

The body heading (the root's rotation about the vertical, ``canon`` angle ``root_y``) covers the whole circle
in turning and spiral walks, and the same body orientation can carry headings 360 degrees apart (angles are
unwrapped within a sequence; other sequences start elsewhere). A regressor fitted to the raw angle averages
such targets into nonsense near the wrap. The paper does not say how it handled this (Section 2 only says
the 42 angles are reduced by PCA); our choice, ``heading="vector"`` (the default), replaces the heading by
``(180/pi) (cos h, sin h)``: a point on a circle of radius 57.3, so a small change of heading moves it by the
same number of units as the change in degrees, and PCA (Eq. 1) weighs it like any other angle. Decoding takes
``atan2``. ``heading="angle"`` keeps the raw (wrapped to [-180, 180)) angle: the literal reading of the paper.
"""

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.motion import canon

HEADING = canon.ANGLE_NAMES.index("root_y")
RADIUS = 180.0 / np.pi
ENCODINGS = ("vector", "angle")


def _check(heading: str) -> None:
    if heading not in ENCODINGS:
        raise VoxposeError(f"regression.heading must be one of {', '.join(ENCODINGS)}, got {heading!r}")


def encode(angles, heading: str = "vector") -> np.ndarray:
    """y' (N, 42) degrees -> regression targets: (N, 43) for ``vector``, (N, 42) for ``angle``."""
    _check(heading)
    angles = np.asarray(angles, dtype=float)
    h = angles[:, HEADING]
    if heading == "angle":
        out = angles.copy()
        out[:, HEADING] = (h + 180.0) % 360.0 - 180.0
        return out
    rest = np.delete(angles, HEADING, axis=1)
    circle = RADIUS * np.stack([np.cos(np.deg2rad(h)), np.sin(np.deg2rad(h))], axis=1)
    return np.concatenate([circle, rest], axis=1)


def decode(targets, heading: str = "vector") -> np.ndarray:
    """Inverse of ``encode``: (N, 43) or (N, 42) -> y' (N, 42) degrees (heading in [-180, 180])."""
    _check(heading)
    targets = np.asarray(targets, dtype=float)
    if heading == "angle":
        return targets.copy()
    h = np.rad2deg(np.arctan2(targets[:, 1], targets[:, 0]))
    return np.insert(targets[:, 2:], HEADING, h, axis=1)


def turn_heading(angles, degrees) -> np.ndarray:
    """y' (N, 42) with ``degrees`` (a number or (N,)) added to the heading, every other angle as it is: the
    pose seen from a frame turned by ``-degrees`` about the vertical (the root's Euler order is Y-X-Z, so
    ``Ry(d) Ry(a0) Rx(a1) Rz(a2)`` only moves ``a0``). Body-frame descriptors (``descriptors.body_frame``)
    regress the heading relative to the reference heading ``h0``: ``turn_heading(y, -h0)``; estimates
    go back with ``turn_heading(y_hat, h0)``."""
    out = np.array(angles, dtype=float)
    out[:, HEADING] += degrees
    return out
