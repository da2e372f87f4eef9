"""Agarwal & Triggs-style silhouette features, measured instead of quoted (Table 1's last row; issue 8).

Agarwal & Triggs (PAMI 2006) describe one silhouette by 2D shape contexts at points of its contour
(``voxpose.descriptors.contour``), vector-quantise them with K-means (100 centres, fitted on the training
silhouettes' shape contexts) into a histogram with soft votes, and regress pose from that histogram with an
RVM. We follow them with the pieces this project already has: ``FeatureModel`` (method ``kmeans``: k-means++
and Lloyd, the soft vote of ``features.frame.SoftVoteRule``, one histogram per image, rows sum to one) and the
same MVRVM regression as every other row of Table 1. Two variants differ only in the views used:

- one camera (``cameras: [c]``), as in their paper;
- all cameras, one histogram per view concatenated (C x 100 features): the "re-learn the regressor for every
  camera setup" alternative the paper argues against. Its features are defined only for rigs with the number
  of cameras it was trained on (``silhouette_features`` refuses others).

The silhouettes are those the voxel pipeline carves (``voxels.degrade.posed_body``: same body model, same placement).
A frame is a gap (no features) when one of its views has no silhouette.
"""

import logging
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from voxpose.descriptors.contour import contour_points, shape_contexts
from voxpose.errors import VoxposeError
from voxpose.features.model import FeatureModel, subsample_indices
from voxpose.voxels.degrade import posed_body
from voxpose.voxels.render import render_silhouettes

log = logging.getLogger(__name__)


def render_contexts(motion, rig, cfg: dict, *, proportions=None, variation=None, follow_subject=True):
    """Shape contexts of every view of every frame of ``motion`` seen by ``rig``.

    ``cfg``: the config's ``claims.contour`` section (``n_points``, ``n_r``, ``n_theta``, ``r_inner``,
    ``r_outer``). Returns ``contexts`` (N, n_r * n_theta) float32, the rows of image ``f * C + c`` being
    ``contexts[offsets[f * C + c]:offsets[f * C + c + 1]]``, and ``offsets`` (F * C + 1,) int64.
    """
    ellipsoids, _ = posed_body(motion, rig, proportions=proportions, variation=variation, follow_subject=follow_subject)
    sc_args = {k: cfg[k] for k in ("n_r", "n_theta", "r_inner", "r_outer")}
    parts = []
    for f in range(motion.n_frames):
        for mask in render_silhouettes(ellipsoids.frame(f), rig):
            parts.append(shape_contexts(contour_points(mask, cfg["n_points"]), **sc_args).astype(np.float32))
        if (f + 1) % 50 == 0:
            log.info("contours %s: frame %d/%d", motion.name, f + 1, motion.n_frames)
    offsets = np.concatenate([[0], np.cumsum([len(p) for p in parts])]).astype(np.int64)
    return np.concatenate(parts), offsets


def _selected_rows(offsets, n_cameras: int, cameras):
    """Row indices of the chosen cameras' images, each row's index ``f * len(cameras) + k``, number of frames."""
    n_frames = (len(offsets) - 1) // n_cameras
    sizes = np.diff(offsets).reshape(n_frames, n_cameras)[:, cameras]
    starts = offsets[:-1].reshape(n_frames, n_cameras)[:, cameras]
    rows = np.concatenate([np.arange(a, a + n) for a, n in zip(starts.ravel(), sizes.ravel(), strict=True)])
    image = np.repeat(np.arange(sizes.size), sizes.ravel())
    return rows.astype(np.intp), image, n_frames


def _selected(contexts, offsets, n_cameras: int, cameras):
    """Rows of the chosen cameras' images and each row's index ``f * len(cameras) + k``; number of frames."""
    rows, image, n_frames = _selected_rows(offsets, n_cameras, cameras)
    return contexts[rows], image, n_frames


def resolve_cameras(cameras, n_cameras: int) -> list:
    """``"all"`` or a list of camera indices -> the list, checked against the rig's ``n_cameras``."""
    chosen = list(range(n_cameras)) if cameras == "all" else [int(c) for c in cameras]
    if not chosen or any(not 0 <= c < n_cameras for c in chosen):
        raise VoxposeError(f"A&T features: cameras {cameras!r} do not exist on a rig of {n_cameras} cameras")
    return chosen


@dataclass(frozen=True)
class ContourSource:
    """One training motion's shape contexts for the codebook: its image ``offsets`` and ``n_cameras`` up front,
    the contexts from ``load()`` only when read, so that the fit holds one motion's contexts at a time."""

    offsets: np.ndarray
    n_cameras: int
    load: Callable[[], np.ndarray]


def fit_codebook(training: list, cameras, cfg: dict, seed: int) -> FeatureModel:
    """K-means codebook and soft-vote rule on the training shape contexts of the chosen views.

    ``training``: a ``ContourSource`` per training motion; ``cfg``: the config's ``claims.at`` section
    (``n_centres``, ``neighbours``, ``fit_subsample``, ``max_iter``). The ``fit_subsample`` rows are drawn
    (``features.model.subsample_indices``) from the chosen views' rows of all motions taken together, as if
    concatenated, and each motion is read once, keeping only its drawn rows: the largest real-data fit (1.9
    million rows of camera 0) peaked at 3.6 GB with every motion in memory.
    """
    n_cams = {source.n_cameras for source in training}
    if len(n_cams) != 1:
        raise VoxposeError(f"A&T features: training motions seen by different numbers of cameras {sorted(n_cams)}")
    n_cams = n_cams.pop()
    chosen = resolve_cameras(cameras, n_cams)
    selected = [_selected_rows(source.offsets, n_cams, chosen)[0] for source in training]
    start = np.cumsum([0] + [len(rows) for rows in selected])
    drawn = subsample_indices(int(start[-1]), cfg["fit_subsample"], seed)
    rows = []
    for k, source in enumerate(training):
        lo, hi = np.searchsorted(drawn, start[k : k + 2])
        contexts = source.load()  # every motion read (and checked), one at a time
        rows.append(contexts[selected[k][drawn[lo:hi] - start[k]]])
    model_cfg = {"n_components": cfg["n_centres"], "kmeans_neighbours": cfg["neighbours"],
                 "fit_subsample": cfg["fit_subsample"], "max_iter": cfg["max_iter"]}  # fmt: skip
    model = FeatureModel.fit_rows("kmeans", np.concatenate(rows), int(start[-1]), model_cfg, seed)
    model.meta |= {"cameras": chosen, "n_cameras": n_cams}
    return model


def silhouette_features(model: FeatureModel, contexts, offsets, n_cameras: int):
    """-> (features (F, len(cameras) * K), counts (F,)): each view's soft histogram, views side by side.

    ``counts`` is the number of shape contexts of the frame's chosen views, 0 (a gap, NaN features) when one
    of them has none. A rig whose number of cameras differs from the training rig's is refused.
    """
    if n_cameras != model.meta["n_cameras"]:
        raise VoxposeError(
            f"A&T features: the codebook was trained on a rig of {model.meta['n_cameras']} cameras, this rig has "
            f"{n_cameras}: silhouette features must be re-learnt for every camera setup"
        )
    cameras = model.meta["cameras"]
    rows, image, n_frames = _selected(contexts, offsets, n_cameras, cameras)
    hist, per_image = model.transform(rows, image, n_frames * len(cameras))
    per_image = per_image.reshape(n_frames, len(cameras))
    features = hist.reshape(n_frames, -1)
    counts = np.where((per_image > 0).all(axis=1), per_image.sum(axis=1), 0)
    features[counts == 0] = np.nan
    return features, counts
