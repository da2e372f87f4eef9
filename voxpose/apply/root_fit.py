"""Where the subject stands: the root position that puts the estimated body on the carved visual hull.

The regressor estimates joint angles only (Section 2), so the skeleton still has to be placed. The hull's
centroid will not do: a long dress or raised arms move the centroid but not the pelvis (in
``tests/apply/test_root_fit.py`` a long dress puts the centroid 32-35 cm below the root). Instead the body
model posed by the estimated angles (``voxpose.apply.posed_body``, the model's output skeleton) is translated
to where it overlaps the hull most: the root is the translation with the most hull voxels whose centres the
translated body fills. The body's own volume does not change with the translation, so this is also the one
with the fewest body voxels outside the hull (and the smallest symmetric difference); extra hull volume
(a dress, the carving's phantom volume) only matters where the body could move inside it. Only a
translation is fitted; the angles stay the regressor's.

Search, per frame, starting from the hull's centroid ``c0``: the body posed at ``c0`` is voxelized on the
hull's grid (``voxpose.voxels.occupancy``), so that a shift by whole voxels moves it exactly.

1. Coarse, global: hull and body occupancy summed into blocks of ``COARSE`` ^ 3 voxels are cross-correlated
   for every shift at once by FFT (zero-padded, so no shift wraps round), and the best block shift is refined
   to a fraction of a block by the vertex of the peak and its neighbours on each axis.
2. Fine, local: from the nearest whole-voxel shift, a hill climb over the six neighbouring shifts counts the
   exact overlap at full resolution until no neighbour is better (ties keep the current shift).
3. Sub-voxel: the overlap falls off linearly on each side of its maximum (by the body's cross-section per
   voxel of shift), so the fraction of a voxel on each axis is the vertex of a symmetric "V" through the best
   shift and its two neighbours (the equiangular fit of stereo matching): exact for a V, 0.5 for a tie.

The climb of step 2 runs as a numba kernel (``voxpose.apply.root_fit_kernels``) when ``voxpose.kernels`` selects it,
with the same integer counts. There is nothing random, so the fit is deterministic. Frames are processed in batches
of ``BATCH``, vectorised within a batch. Frames without estimate or with an empty hull get ``NaN``.
"""

import logging

import numpy as np
from scipy import fft

from voxpose.apply import root_fit_kernels
from voxpose.apply.posed_body import posed_body
from voxpose.errors import VoxposeError
from voxpose.kernels import use_numba
from voxpose.motion.output_skeleton import OutputSkeleton
from voxpose.voxels.occupancy import occupied_voxels
from voxpose.voxels.sequence import VoxelSequence

log = logging.getLogger(__name__)

COARSE = 3  # voxels per coarse block side
BATCH = 32  # frames fitted together
MAX_CLIMB = 20  # hill-climb steps (one voxel each); the coarse estimate is within about two
_STEPS = np.array([[0, 0, 0], [-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]])


def hull_centroids(seq: VoxelSequence) -> np.ndarray:
    """(F, 3) mean voxel centre of each frame (metres), NaN for empty frames."""
    counts = np.diff(seq.offsets)
    frame = np.repeat(np.arange(seq.n_frames), counts)
    centre = (seq.ijk + 0.5) * seq.l_res
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.stack([np.bincount(frame, centre[:, a], seq.n_frames) for a in range(3)], axis=1) / counts[:, None]


def fit_roots(seq: VoxelSequence, angles, valid, skeleton: OutputSkeleton, *, progress_every: int = 500,
              name: str = "input") -> np.ndarray:  # fmt: skip
    """(F, 3) root positions (metres, the voxels' coordinates) of y' ``angles`` (F, 42) on ``skeleton``, fitted
    to each frame's hull (module docstring); NaN where ``valid`` is false or the hull is empty. A progress
    line is logged every ``progress_every`` frames (0: none), ``name`` labelling it."""
    angles = np.asarray(angles, dtype=float)
    todo = np.flatnonzero(np.asarray(valid, dtype=bool) & (np.diff(seq.offsets) > 0))
    start = hull_centroids(seq)
    roots = np.full((seq.n_frames, 3), np.nan)
    for b in range(0, len(todo), BATCH):
        frames = todo[b : b + BATCH]
        body_frame, body = occupied_voxels(posed_body(angles[frames], skeleton, start[frames]), seq.l_res)
        if np.unique(body_frame).size < len(frames):
            raise VoxposeError(f"root fit {name}: the body model fills no voxel of {seq.l_res:.3g} m")
        counts = np.diff(seq.offsets)[frames]
        hull_frame = np.repeat(np.arange(len(frames)), counts)
        hull = seq.ijk[np.arange(counts.sum()) + np.repeat(seq.offsets[frames] - np.cumsum(counts) + counts, counts)]
        hull = hull.astype(np.int64)
        shift = _coarse_shifts(hull_frame, hull, body_frame, body, len(frames))
        roots[frames] = start[frames] + _fine_shifts(hull_frame, hull, body_frame, body, shift) * seq.l_res
        done = b + len(frames)
        if progress_every and done // progress_every > b // progress_every:
            log.info("root fit %s: %d/%d frames", name, done, len(todo))
    return roots


def _box(frame, ijk, n):
    """Per-frame lowest index (n, 3) and extent (n, 3) of voxels sorted by frame (every frame non-empty)."""
    starts = np.searchsorted(frame, np.arange(n))
    lo = np.minimum.reduceat(ijk, starts, axis=0)
    return lo, np.maximum.reduceat(ijk, starts, axis=0) - lo + 1


def _flat(frame, rel, shape):
    """Flat indices into an (n, *shape) array of per-frame voxel indices ``rel``."""
    return ((frame * shape[0] + rel[:, 0]) * shape[1] + rel[:, 1]) * shape[2] + rel[:, 2]


def _counts(frame, ijk, lo, shape, n):
    """Voxel counts (n, *shape) at ``ijk - lo[frame]`` (all in range)."""
    return np.bincount(_flat(frame, ijk - lo[frame], shape), minlength=n * int(np.prod(shape))).reshape(n, *shape)


def _vertex(minus, centre, plus):
    """Offset in [-0.5, 0.5] of a symmetric V's apex through (-1, minus), (0, centre), (1, plus); 0 if flat."""
    drop = centre - np.minimum(minus, plus)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(drop > 0, (plus - minus) / (2.0 * drop), 0.0)


def _coarse_shifts(hull_frame, hull, body_frame, body, n) -> np.ndarray:
    """(n, 3) whole-voxel body shifts nearest the best coarse shift (module docstring, step 1)."""
    hull_c, body_c = hull // COARSE, body // COARSE
    lo_h, ext_h = _box(hull_frame, hull_c, n)
    lo_b, ext_b = _box(body_frame, body_c, n)
    shape = tuple(fft.next_fast_len(int(s)) for s in (ext_h + ext_b - 1).max(axis=0))
    h = _counts(hull_frame, hull_c, lo_h, shape, n).astype(np.float64)
    m = _counts(body_frame, body_c, lo_b, shape, n).astype(np.float64)
    axes = (1, 2, 3)
    corr = fft.irfftn(fft.rfftn(h, axes=axes) * np.conj(fft.rfftn(m, axes=axes)), s=shape, axes=axes)
    peak = np.stack(np.unravel_index(corr.reshape(n, -1).argmax(axis=1), shape), axis=1)
    rows = np.arange(n)
    frac = np.empty((n, 3))
    for a in range(3):
        side = np.zeros((2, n, 3), dtype=np.int64)
        side[0, :, a], side[1, :, a] = -1, 1
        minus, plus = (corr[(rows, *((peak + s) % shape).T)] for s in side)
        frac[:, a] = _vertex(minus, corr[(rows, *peak.T)], plus)
    lag = np.where(peak < ext_h, peak, peak - np.asarray(shape))  # the correlation's lag: body cell -> hull cell
    return np.rint(COARSE * (lag + frac + lo_h - lo_b)).astype(np.int64)


def _fine_shifts(hull_frame, hull, body_frame, body, shift) -> np.ndarray:
    """(n, 3) body shifts in voxels, whole-voxel hill climb then sub-voxel vertex (module docstring, steps 2-3)."""
    n = len(shift)
    lo, ext = _box(hull_frame, hull, n)
    lo -= 2  # a margin of two empty layers: a body voxel one step from the hull's box stays inside the grid
    shape = tuple(int(s) + 4 for s in ext.max(axis=0))
    occupied = np.zeros(n * int(np.prod(shape)), dtype=bool)
    occupied[_flat(hull_frame, hull - lo[hull_frame], shape)] = True
    size = np.asarray(shape)
    offsets = _STEPS @ [shape[1] * shape[2], shape[2], 1]  # the steps as offsets of the flat index
    scores = np.zeros((n, len(_STEPS)))
    if use_numba():  # the same climb in one loop (voxpose.apply.root_fit_kernels)
        still = root_fit_kernels.climb(occupied, size, offsets, _STEPS, body_frame, body, shift, lo, scores,
                                       MAX_CLIMB)  # fmt: skip
        if still:
            log.warning("root fit: %d frames still climbing after %d steps", still, MAX_CLIMB)
        return shift + _fractions(scores)
    active = np.ones(n, dtype=bool)
    for _ in range(MAX_CLIMB):
        keep = active[body_frame]
        frame = body_frame[keep]
        rel = body[keep] + (shift - lo)[frame]
        near = ((rel >= 1) & (rel <= size - 2)).all(axis=1)  # the others miss the hull at every step
        frame, flat = frame[near], _flat(frame[near], rel[near], shape)
        for s, offset in enumerate(offsets):
            scores[active, s] = np.bincount(frame, occupied[flat + offset], minlength=n)[active]
        best = scores.argmax(axis=1)  # the first maximum: the current shift on a tie
        moved = active & (best > 0)
        shift[moved] += _STEPS[best[moved]]
        active = moved
        if not active.any():
            break
    else:
        log.warning("root fit: %d frames still climbing after %d steps", int(active.sum()), MAX_CLIMB)
    return shift + _fractions(scores)


def _fractions(scores) -> np.ndarray:
    """(n, 3) sub-voxel shifts from the overlaps (n, 7) at the best whole-voxel shift and its neighbours (step 3)."""
    return np.stack([_vertex(scores[:, 1 + 2 * a], scores[:, 0], scores[:, 2 + 2 * a]) for a in range(3)], axis=1)
