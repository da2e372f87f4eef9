"""3D shape context (3DSC) descriptors on point sets: the reference definition and the shared bin geometry.

Sun et al. 2006, Section 4 and Figure 3. A descriptor centred at a basis voxel is a histogram of the
relative positions of the surface voxels in a spherical support volume, split into ``n_r`` log-spaced
shells (Eq. 4), ``n_e`` elevation and ``n_a`` azimuth sectors: ``n_r * n_e * n_a`` bins, flat index
``(i_r * n_e + i_e) * n_a + i_a``. The three features of Section 4 are all here: the frame is the world
frame (no alignment to a normal, so the descriptor is rotation dependent), votes are soft (optional) and
every vote is weighted by ``1 / cbrt(V)`` of its bin's volume. :mod:`voxpose.descriptors.lut` is the
lookup-table fast path on voxel grids; it calls :func:`offset_votes` below on integer offsets, so both
paths share one definition of a vote.

Everything is computed in voxel units (offsets divided by ``l_res``): ``R_min = r_min`` voxels,
``R_max = r_max * h_sub / l_res`` voxels (20 in the paper, where ``l_res = h_sub / 60``), bin volumes
in ``l_res**3``. Descriptors therefore depend only on the shape measured in voxels, which is what makes
them scale invariant (the paper sets ``l_res = h_sub / 60``) and translation invariant.

Conventions (the paper fixes none of them; each is tested):

- Axes: world frame, Y up. Elevation ``theta = atan2(hypot(x, z), y)`` is measured from +Y, in
  [0, 180] degrees; azimuth ``phi = atan2(z, x)`` mod 360 is measured in the ground plane from +X
  towards +Z (+Z is 90 degrees), in [0, 360) degrees.
- Support: a point votes iff ``R_min <= r < R_max``; the centre itself never votes. Shell ``i`` is
  ``[R_i, R_i+1)``, elevation and azimuth sectors are ``[lo, hi)`` as well, except that the last
  elevation sector includes 180 degrees.
- Continuous bin coordinates ``t`` (bin ``k`` covers ``[k, k+1)``):
  ``t_r = n_r * ln(r / R_min) / ln(R_max / R_min)`` (so the shell boundaries are exactly Eq. 4),
  ``t_e = theta * n_e / 180``, ``t_a = phi * n_a / 360``.
- Hard voting: a point votes 1 for the bin ``(floor t_r, floor t_e, floor t_a)``.
- Soft voting (Section 4, second bullet: "a voxel in the vicinity of a boundary gives divided votes to
  the bins on both sides"): linear interpolation in the continuous bin coordinates with bin centres at
  integers, ``s = t - 1/2``, along each axis independently (trilinear), wrapping in azimuth and clamping
  at the radial ends and at the poles. A vote's total mass is 1 before weighting; a point exactly on a
  boundary splits it equally between the two bins; a point at the centre of a bin gives it all.
  Interpolation is in log-r, the coordinate in which the shells are evenly spaced.
- Vertical axis: a point exactly above or below the centre (``x = z = 0`` after snapping) has no
  azimuth; it lies on every azimuth boundary, so in both modes it spreads its vote evenly over the
  ``n_a`` azimuth bins of its ring, the one rule that commutes with rotation about the vertical.
- Weights: each (partial) vote is multiplied by ``1 / cbrt(V)`` of the bin it lands in, with ``V`` the
  bin's volume in ``l_res**3``.
- Exact boundaries on the grid: voxel offsets are integers in voxel units and often fall exactly on a
  boundary (``R_min = 2`` voxels; ``R_2 = 2 * sqrt(10)`` has ``r**2 = 40`` at the defaults; elevation 90
  degrees when ``n_e`` is even; azimuth 0, 90, 180, 270 degrees). So that rounding never flips such a
  vote, offsets ``(p - c) / l_res`` within 1e-9 of an integer are snapped to it, and continuous bin
  coordinates within 1e-9 of an integer (boundaries) or, in soft voting, of a half-integer (bin
  centres) are snapped to it; no point off a boundary of a grid of realistic size comes that close.
  The fast path feeds exact integers through the same code, so both paths agree on every boundary by
  construction.
- Normalisation (off by default; the paper does not normalise): ``normalise=True`` divides each
  descriptor by its sum (L1), leaving empty descriptors at zero.
"""

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from voxpose.descriptors.settings import DescriptorSettings
from voxpose.errors import VoxposeError
from voxpose.validation import integer, positive_number

SNAP = 1e-9
"""Offsets and bin coordinates this close to an integer (soft: bin centres, too) are snapped to it."""

_CHUNK_PAIRS = 1 << 19
"""Centre-point pairs the reference processes at once, to bound its memory."""


def _snap(values: np.ndarray) -> np.ndarray:
    """Snap values within ``SNAP`` of an integer onto it; ``+ 0.0`` also turns -0.0 into +0.0."""
    nearest = np.rint(values)
    return np.where(np.abs(values - nearest) <= SNAP, nearest, values) + 0.0


@dataclass(frozen=True)
class BinGeometry:
    """Bins of the 3DSC support volume in voxel units (Section 4, Eq. 4, Figure 3).

    Hashable and comparable, so it keys the lookup-table cache of the fast path.

    Parameters
    ----------
    n_r, n_e, n_a : int
        Radial, elevation and azimuth divisions (the paper: 4, 5, 10).
    r_min, r_max : float
        ``R_min`` and ``R_max`` in voxels (the paper: 2 and ``h_sub / 3 / l_res`` = 20).
    """

    n_r: int
    n_e: int
    n_a: int
    r_min: float
    r_max: float

    def __post_init__(self):
        for name in ("n_r", "n_e", "n_a"):
            object.__setattr__(self, name, integer(getattr(self, name), f"shape context: {name}"))
        object.__setattr__(self, "r_min", positive_number(self.r_min, "shape context: r_min"))
        object.__setattr__(self, "r_max", positive_number(self.r_max, "shape context: r_max"))
        if self.r_min >= self.r_max:
            raise VoxposeError(
                f"shape context: R_min = r_min * l_res ({self.r_min:g} voxels) must be smaller than "
                f"R_max = r_max * h_sub ({self.r_max:g} voxels)"
            )

    @classmethod
    def from_settings(cls, settings: DescriptorSettings, h_sub_voxels) -> "BinGeometry":
        """Geometry of a descriptor's settings (``r_min`` in voxels, ``r_max`` a fraction of ``h_sub``) for a
        subject ``h_sub_voxels = h_sub / l_res`` voxels tall (60 in the paper)."""
        h_sub_voxels = positive_number(h_sub_voxels, "shape context: h_sub / l_res")
        r_max = positive_number(settings.r_max, "shape context: r_max")
        return cls(n_r=settings.n_r, n_e=settings.n_e, n_a=settings.n_a, r_min=settings.r_min,
                   r_max=r_max * h_sub_voxels)  # fmt: skip

    def empty_support_error(self) -> VoxposeError:
        """The error for a support that holds no integer voxel offset (both fast paths raise it)."""
        return VoxposeError(
            f"shape context: no voxel offset lies in the support ({self.r_min:g} <= r < {self.r_max:g} voxels); "
            "raise r_max or h_sub / l_res"
        )

    @property
    def n_bins(self) -> int:
        return self.n_r * self.n_e * self.n_a

    def bin_index(self, i_r, i_e, i_a):
        """Flat bin index ``(i_r * n_e + i_e) * n_a + i_a``."""
        return (np.asarray(i_r) * self.n_e + i_e) * self.n_a + i_a

    @cached_property
    def radial_boundaries(self) -> np.ndarray:
        """``(n_r + 1,)`` shell radii ``R_i`` in voxels, log-spaced from ``R_min`` to ``R_max`` (Eq. 4)."""
        i = np.arange(self.n_r + 1)
        return np.exp(np.log(self.r_min) + i / self.n_r * np.log(self.r_max / self.r_min))

    @cached_property
    def bin_volumes(self) -> np.ndarray:
        """``(n_bins,)`` bin volumes in voxels: shell volume x solid-angle fraction of the sector."""
        shells = np.diff(self.radial_boundaries**3) / 3.0
        cos_e = np.cos(np.linspace(0.0, np.pi, self.n_e + 1))
        bands = cos_e[:-1] - cos_e[1:]
        sector = 2.0 * np.pi / self.n_a
        return (shells[:, None, None] * bands[None, :, None] * np.full(self.n_a, sector)).ravel()

    @cached_property
    def bin_weights(self) -> np.ndarray:
        """``(n_bins,)`` vote weights ``1 / cbrt(V)`` (Section 4, second bullet), V in voxels."""
        return 1.0 / np.cbrt(self.bin_volumes)

    def coordinates(self, offsets: np.ndarray):
        """Continuous bin coordinates of offsets in voxels, snapped near integers.

        Returns ``(t_r, t_e, t_a, pole)``, each ``(P,)``: ``t_r`` is ``-inf`` at the centre; ``t_a`` is in
        ``[0, n_a]`` (``n_a`` only for azimuths a hair below 360) and meaningless where ``pole``.
        """
        x, y, z = offsets[:, 0], offsets[:, 1], offsets[:, 2]
        r = np.sqrt(x * x + y * y + z * z)
        with np.errstate(divide="ignore", invalid="ignore"):
            t_r = _snap(self.n_r * np.log(r / self.r_min) / math.log(self.r_max / self.r_min))
        rho = np.hypot(x, z)
        t_e = _snap(np.arctan2(rho, y) * (self.n_e / np.pi))
        t_a = _snap(np.mod(np.arctan2(z, x), 2.0 * np.pi) * (self.n_a / (2.0 * np.pi)))
        return t_r, t_e, t_a, rho == 0.0


def _hard_axis(t: np.ndarray, n: int, wrap: bool):
    """One bin per point along an axis: ``floor(t)``, wrapped or clamped into ``[0, n)``."""
    k = np.floor(t).astype(np.int64)
    k = np.mod(k, n) if wrap else np.clip(k, 0, n - 1)
    return k[:, None], np.ones((len(t), 1))


def soft_axis(t: np.ndarray, n: int, wrap: bool):
    """Two bins per point along an axis: linear interpolation between bin centres at ``k + 1/2``."""
    s = _snap(t - 0.5)  # a point at a bin centre gives it all, with no round-off vote next door
    lo = np.floor(s)
    frac = s - lo
    k = lo.astype(np.int64)[:, None] + np.array([0, 1])
    k = np.mod(k, n) if wrap else np.clip(k, 0, n - 1)
    return k, np.stack([1.0 - frac, frac], axis=1)


def _spread_axis(count: int, n: int):
    """All ``n`` bins of an axis with equal shares, for ``count`` points (azimuth on the vertical axis)."""
    return np.broadcast_to(np.arange(n), (count, n)), np.full((count, n), 1.0 / n)


def offset_votes(offsets, geometry: BinGeometry, *, soft: bool):
    """The weighted votes of relative positions: the one definition of a vote both paths share.

    Parameters
    ----------
    offsets : (P, 3) float array
        Point minus centre, in voxels (``l_res``), world frame, Y up; already snapped (see the module).
    geometry : BinGeometry
    soft : bool
        Soft (trilinear) or hard voting; see the module docstring for the exact rules.

    Returns
    -------
    owner, bins, weights : (Q,) arrays
        Offset index (into ``offsets``), flat bin index and weighted vote of every partial vote, in no
        particular order. Offsets outside the support have none; partial votes of zero mass are dropped.
    """
    offsets = np.asarray(offsets, dtype=np.float64).reshape(-1, 3)
    g = geometry
    t_r, t_e, t_a, pole = g.coordinates(offsets)
    inside = np.flatnonzero((t_r >= 0.0) & (t_r < g.n_r))
    axis = soft_axis if soft else _hard_axis
    k_r, f_r = axis(t_r[inside], g.n_r, wrap=False)
    k_e, f_e = axis(t_e[inside], g.n_e, wrap=False)
    on_axis = pole[inside]
    azimuths = [
        (~on_axis, axis(t_a[inside][~on_axis], g.n_a, wrap=True)),
        (on_axis, _spread_axis(int(on_axis.sum()), g.n_a)),
    ]
    owners, bins, weights = [], [], []
    for sel, (k_a, f_a) in azimuths:
        b = g.bin_index(k_r[sel][:, :, None, None], k_e[sel][:, None, :, None], k_a[:, None, None, :])
        f = f_r[sel][:, :, None, None] * f_e[sel][:, None, :, None] * f_a[:, None, None, :]
        keep = f > 0.0
        owners.append(np.broadcast_to(inside[sel][:, None, None, None], b.shape)[keep])
        bins.append(b[keep])
        weights.append(f[keep] * g.bin_weights[b[keep]])
    return np.concatenate(owners), np.concatenate(bins), np.concatenate(weights)


def normalise_rows(descriptors: np.ndarray) -> np.ndarray:
    """Divide each descriptor by its sum (L1), in place; all-zero descriptors stay zero."""
    total = descriptors.sum(axis=1, keepdims=True)
    np.divide(descriptors, total, out=descriptors, where=total > 0)
    return descriptors


def _as_points(name: str, values) -> np.ndarray:
    try:
        arr = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise VoxposeError(f"shape context: {name} must be an (N, 3) array of numbers") from None
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise VoxposeError(f"shape context: {name} must have shape (N, 3), got {arr.shape}")
    if len(arr) == 0:
        raise VoxposeError(f"shape context: {name} is empty")
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        raise VoxposeError(f"shape context: {name} row {int(np.argmax(bad))} is not finite: {arr[bad][0]}")
    return arr


def shape_contexts(points, centres, *, l_res, h_sub, **params) -> np.ndarray:
    """3D shape contexts of a point set at given centres, by brute force (the reference definition).

    Parameters
    ----------
    points : (N, 3) array
        Surface points (voxel centres) in metres, world frame, Y up.
    centres : (M, 3) array
        Descriptor centres (basis voxels) in metres.
    l_res : float
        Voxel size in metres; offsets are measured in it.
    h_sub : float
        Subject height in metres.
    **params
        The descriptor's settings (``voxpose.descriptors.settings.DescriptorSettings``: divisions ``n_r``,
        ``n_e``, ``n_a``; ``r_min`` in units of ``l_res``; ``r_max`` a fraction of ``h_sub``; ``soft`` voting;
        ``normalise``), the paper's where not given.

    Returns
    -------
    (M, n_r * n_e * n_a) float64 array
        Descriptor ``m`` at ``centres[m]``, bin ``(i_r * n_e + i_e) * n_a + i_a``.
    """
    l_res = positive_number(l_res, "shape context: l_res")
    h_sub = positive_number(h_sub, "shape context: h_sub")
    settings = DescriptorSettings.from_config(params, "shape context")
    geometry = BinGeometry.from_settings(settings, h_sub / l_res)
    soft, normalise = settings.soft, settings.normalise
    points = _as_points("points", points)
    centres = _as_points("centres", centres)
    n_bins = geometry.n_bins
    out = np.zeros((len(centres), n_bins))
    step = max(1, _CHUNK_PAIRS // len(points))
    for start in range(0, len(centres), step):
        chunk = centres[start : start + step]
        offsets = _snap((points[None, :, :] - chunk[:, None, :]) / l_res).reshape(-1, 3)
        owner, bins, weights = offset_votes(offsets, geometry, soft=soft)
        flat = (owner // len(points)) * n_bins + bins
        out[start : start + len(chunk)] = np.bincount(flat, weights, minlength=len(chunk) * n_bins).reshape(
            len(chunk), n_bins
        )
    return normalise_rows(out) if normalise else out
