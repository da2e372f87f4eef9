"""A motion (or real silhouettes) -> a voxel sequence: silhouettes, carving, surface and basis voxels.

Section 4 and Figure 2, per frame: the visual hull at ``l_res = h_sub / 60``, its surface voxels and
about 200 basis voxels. ``h_sub`` is measured once per sequence, "after processing the first frame using
a moderate resolution (e.g. l_res = 0.05 m)" (``voxels.carve.vertical_extent`` of that hull), and kept for
every frame. If the first frame's hull is empty, the first frame with a non-empty hull is used instead
(``h_sub_frame`` records which).

Synthetic data (``voxelize_motion``): the body model of Section 6 (``voxpose.voxels.body``) is rendered exactly
into every camera of the rig (``voxpose.voxels.render``). Motions travel further than a capture volume (a
200-frame walk covers about 8 m), so by default (``follow_subject=True``) each frame's body is moved
horizontally so that its root joint lies above the rig's centre ``Rig.target``; heights are kept. The
shape descriptors downstream are translation invariant, so this changes nothing but keeps every frame in
view; ``shifts`` records the translation (add it back to the voxel centres' world coordinates to undo it).

Real data (``voxelize_silhouettes``): frames of (C, H, W) silhouettes, e.g. from
``voxpose.voxels.silhouettes``, go through the same carving, surface and basis code.

A frame whose silhouettes have no common voxel is logged with its index and flagged in ``empty`` (its
voxel arrays are empty), never dropped, so frame numbers stay aligned with the poses.
"""

import itertools
import logging

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.voxels.body import body_ellipsoids
from voxpose.voxels.cameras import Rig
from voxpose.voxels.carve import Carver, EmptyHullError, vertical_extent
from voxpose.voxels.render import render_silhouettes
from voxpose.voxels.sequence import VoxelSequence
from voxpose.voxels.settings import DEFAULTS
from voxpose.voxels.surface import basis_indices, surface_mask

log = logging.getLogger(__name__)

H_SUB_RESOLUTION = 0.05  # metres: the "moderate resolution" of Section 4 for measuring h_sub


def _check_fraction(l_res_fraction) -> float:
    if not (isinstance(l_res_fraction, int | float) and 0 < l_res_fraction < 1):
        raise VoxposeError(f"voxelize: l_res_fraction must lie in (0, 1), got {l_res_fraction!r}")
    return float(l_res_fraction)


def voxelize_silhouettes(
    frames,
    rig: Rig,
    *,
    l_res_fraction: float = DEFAULTS.l_res_fraction,
    min_views: int | None = DEFAULTS.min_views,
    n_basis: int = DEFAULTS.n_basis,
    seed: int = 0,
    keep_silhouettes: bool = False,
    progress_every: int = 50,
    n_frames: int | None = None,
    shifts=None,
    name: str = "silhouettes",
) -> VoxelSequence:
    """Voxelise frames of silhouettes (an iterable of (C, H, W) bool arrays) from ``rig``.

    ``l_res = h_sub * l_res_fraction`` with h_sub measured on the first frame with a non-empty hull
    (Section 4); ``min_views`` as in ``voxels.carve.Carver``; ``n_basis`` and ``seed`` as in
    ``voxels.surface.basis_indices`` (the same seed for every frame, so a frame's basis depends on its voxels
    alone). ``n_frames`` (if known) only completes the progress lines, logged every ``progress_every``
    frames (0: none); ``shifts`` (F, 3) is stored as given (``voxelize_motion``); ``name`` labels the log lines.
    """
    fraction = _check_fraction(l_res_fraction)
    iterator = iter(frames)
    coarse = Carver(rig, H_SUB_RESOLUTION, min_views=min_views)
    pending, h_sub = [], None
    for sil in iterator:
        pending.append(sil)
        ijk = coarse(sil)
        if len(ijk):
            h_sub = vertical_extent(ijk, H_SUB_RESOLUTION)
            break
    if h_sub is None:
        raise EmptyHullError(f"voxelize {name}: no frame has a non-empty visual hull ({len(pending)} frames)")
    h_sub_frame = len(pending) - 1
    l_res = h_sub * fraction
    log.info("voxelize %s: h_sub %.3f m (frame %d), l_res %.4f m", name, h_sub, h_sub_frame, l_res)
    carver = Carver(rig, l_res, min_views=min_views)
    total = "?" if n_frames is None else str(n_frames)
    voxels, surfaces, bases, empty, kept = [], [], [], [], []
    for f, sil in enumerate(itertools.chain(pending, iterator)):
        ijk = carver(sil)
        mask = surface_mask(ijk)
        on_surface = np.flatnonzero(mask)
        basis = on_surface[basis_indices(ijk[on_surface], n_basis, seed)]
        voxels.append(ijk)
        surfaces.append(mask)
        bases.append(basis)
        empty.append(len(ijk) == 0)
        if keep_silhouettes:
            kept.append(np.asarray(sil, dtype=bool))
        if len(ijk) == 0:
            log.warning("voxelize %s: frame %d: empty visual hull (the silhouettes do not intersect)", name, f)
        if progress_every and (f + 1) % progress_every == 0:
            counts = (len(ijk), len(on_surface), len(basis))
            log.info("voxelize %s: frame %d/%s: %d voxels, %d surface, %d basis", name, f + 1, total, *counts)
    n_done = len(empty)
    if shifts is None:
        shifts = np.zeros((n_done, 3))
    shifts = np.asarray(shifts, dtype=float)
    if shifts.shape != (n_done, 3):
        raise VoxposeError(f"voxelize {name}: shifts have shape {shifts.shape}, expected ({n_done}, 3)")
    empty = np.array(empty, dtype=bool)
    if empty.any():
        where = np.flatnonzero(empty).tolist()
        log.warning("voxelize %s: %d of %d frames have an empty hull: %s", name, len(where), n_done, where)
    return VoxelSequence(
        l_res=l_res,
        h_sub=h_sub,
        h_sub_frame=h_sub_frame,
        ijk=np.concatenate(voxels).astype(np.int32),
        offsets=np.concatenate([[0], np.cumsum([len(v) for v in voxels])]).astype(np.int64),
        surface=np.concatenate(surfaces),
        basis=np.concatenate(bases).astype(np.int32),
        basis_offsets=np.concatenate([[0], np.cumsum([len(b) for b in bases])]).astype(np.int64),
        empty=empty,
        shifts=shifts,
        silhouettes=np.stack(kept) if keep_silhouettes else None,
    )


def subject_shifts(motion, rig: Rig) -> np.ndarray:
    """(F, 3) horizontal translations putting the root joint of every frame above ``rig.target``."""
    shifts = np.zeros((motion.n_frames, 3))
    target = rig.target
    shifts[:, 0] = target[0] - motion.positions[:, 0, 0]
    shifts[:, 2] = target[2] - motion.positions[:, 0, 2]
    return shifts


def voxelize_motion(
    motion,
    rig: Rig,
    *,
    proportions=None,
    variation=None,
    l_res_fraction: float = DEFAULTS.l_res_fraction,
    min_views: int | None = DEFAULTS.min_views,
    n_basis: int = DEFAULTS.n_basis,
    seed: int = 0,
    follow_subject: bool = DEFAULTS.follow_subject,
    keep_silhouettes: bool = False,
    progress_every: int = 50,
) -> VoxelSequence:
    """Render the body model of a ``MotionData`` into ``rig`` and voxelise every frame (module docstring).

    ``proportions`` overrides the body model's sizes (``voxels.body.DEFAULT_PROPORTIONS``), ``variation`` gives
    this motion's body its own girths and lengths (``voxels.body_variation``); the other arguments
    are those of ``voxelize_silhouettes``.
    """
    _check_fraction(l_res_fraction)
    ellipsoids = body_ellipsoids(motion, proportions, variation)
    shifts = subject_shifts(motion, rig) if follow_subject else np.zeros((motion.n_frames, 3))
    ellipsoids = ellipsoids.translated(shifts)
    frames = (render_silhouettes(ellipsoids.frame(f), rig) for f in range(motion.n_frames))
    return voxelize_silhouettes(
        frames,
        rig,
        l_res_fraction=l_res_fraction,
        min_views=min_views,
        n_basis=n_basis,
        seed=seed,
        keep_silhouettes=keep_silhouettes,
        progress_every=progress_every,
        n_frames=motion.n_frames,
        shifts=shifts,
        name=motion.name,
    )
