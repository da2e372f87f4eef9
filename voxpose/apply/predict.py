"""A trained model applied to new data: calibrated silhouettes (or carved voxels) -> 42 angles per frame -> BVH.

Every frame goes through the training pipeline unchanged (Sections 4-5 and 3): carving at ``l_res = h_sub *
l_res_fraction`` with the model's ``min_views``, surface and basis voxels with the model's ``n_basis`` and seed
(``voxels.voxelize.voxelize_silhouettes``), 3D shape contexts (``ShapeContextTable``) rounded to float32 as the
workflow stores them, the feature transformation (Eq. 5), the MVRVM in pose-PCA space and the inverse PCA and
heading decoding (with body-frame descriptors, in the frame of each hull's reference heading, added back:
``voxpose.descriptors.body_frame``; the model file's descriptor says which frame). Given the same silhouettes as the
workflow, the estimates are the workflow's, number for number.

Gaps. A frame whose silhouettes have no common voxel (an empty hull) has no descriptors and gets no
estimate: it is logged, its ``valid`` flag is false, its CSV row holds ``NaN`` angles, and in the BVH (which
cannot hold a missing value) it is the skeleton's rest pose (every rotation channel 0, the canonical T-pose)
at the root position of the nearest earlier frame with an estimate (the first later one for leading gaps):
an obvious non-pose, never an interpolated or repeated estimate.

Root position. The regressor estimates joint angles only (Section 2). So that the skeleton moves with the
subject, the BVH root is put where the body model posed by the estimated angles (after smoothing) on the
model's output skeleton, scaled to the subject's measured height ``h_sub`` (``posed_body.subject_skeleton``),
best overlaps each frame's visual hull (``voxpose.apply.root_fit``; not the hull's centroid, which a dress or
raised arms move), in world metres: minus the re-centring ``shifts`` of synthetic voxel files. The BVH is
written on that scaled skeleton, so its feet reach the floor whatever the subject's size.

Temporal smoothing (``smooth`` > 0; off by default, the paper estimates every frame independently): each
angle, unwrapped over time, is convolved with a Gaussian of standard deviation ``smooth`` frames
(``scipy.ndimage.gaussian_filter1d``, edges repeated), separately within each run of frames without gaps;
``benchmarks/smoothing_effect.py`` measures what it does to the test error.
"""

import logging
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter1d

from voxpose.apply.model_file import PoseModel
from voxpose.apply.posed_body import subject_skeleton
from voxpose.apply.root_fit import fit_roots
from voxpose.descriptors.sequence import describe_sequence
from voxpose.descriptors.settings import DescriptorSettings
from voxpose.errors import VoxposeError
from voxpose.evaluation import metrics
from voxpose.features.model import FrameFeatures
from voxpose.motion import canon
from voxpose.motion.output_skeleton import OutputSkeleton
from voxpose.motion.rotations import unwrap_degrees
from voxpose.regression import pose_encoding
from voxpose.voxels.sequence import VoxelSequence
from voxpose.voxels.voxelize import voxelize_silhouettes

log = logging.getLogger(__name__)

_FRACTION_TOLERANCE = 1e-6


@dataclass
class Prediction:
    """Estimates for every frame of one sequence.

    angles : (F, 42) y' in degrees, NaN rows at gaps.
    valid : (F,) frames with an estimate (non-empty hull).
    root : (F, 3) fitted root position in the voxels' coordinates (metres, ``apply.root_fit``), NaN at gaps.
    voxels : the carved sequence the estimates come from.
    frames : (F,) frame numbers (of the silhouette files; 0.. for voxel files).
    fps : frame rate written to the BVH.
    true_angles : (F, 42) ground truth when the input carries it, else None.
    smooth : the temporal smoothing applied (Gaussian sigma in frames; 0: none).
    novelty : how far the input lies from the training data (features/novelty.py), None without a range.
    skeleton : the output skeleton scaled to the subject (module docstring), None when not known.
    """

    angles: np.ndarray
    valid: np.ndarray
    root: np.ndarray
    voxels: VoxelSequence
    frames: np.ndarray
    fps: float
    true_angles: np.ndarray | None = None
    smooth: float = 0.0
    novelty: dict | None = None
    skeleton: OutputSkeleton | None = None

    def world_root(self) -> np.ndarray:
        """(F, 3) root positions in the recording's world frame: the voxel frame minus the ``shifts``."""
        return self.root - self.voxels.shifts

    def error(self) -> float | None:
        """Full-body error (mean over angles of the RMS over frames, Eq. 6) on the frames with an estimate."""
        if self.true_angles is None or not self.valid.any():
            return None
        return metrics.full_body_error(self.true_angles[self.valid], self.angles[self.valid])


def carve(model: PoseModel, frames, rig, *, n_frames=None, name="silhouettes") -> VoxelSequence:
    """Silhouette frames (iterable of (C, H, W) bool) -> voxels, with the model's carving settings."""
    v = model.voxels
    return voxelize_silhouettes(frames, rig, l_res_fraction=v["l_res_fraction"], min_views=v["min_views"],
                                n_basis=v["n_basis"], seed=v["seed"], n_frames=n_frames, name=name)  # fmt: skip


def check_voxels(model: PoseModel, seq: VoxelSequence, meta: dict, path) -> None:
    """Refuse voxels carved with other settings than the model's (their descriptors would mean other things)."""
    fraction = seq.l_res / seq.h_sub
    expected = model.voxels["l_res_fraction"]
    if abs(fraction - expected) > _FRACTION_TOLERANCE * expected:
        raise VoxposeError(f"{path}: voxels carved at l_res = h_sub x {fraction:.6g}, the model needs {expected:.6g}")
    n_basis = meta.get("params", {}).get("n_basis")
    if n_basis is not None and int(n_basis) != model.voxels["n_basis"]:
        raise VoxposeError(f"{path}: voxels with {n_basis} basis voxels per frame, the model needs "
                           f"{model.voxels['n_basis']}")  # fmt: skip


def describe(model: PoseModel, seq: VoxelSequence) -> tuple[list, np.ndarray | None]:
    """3D shape contexts (B_f, bins) of every frame (empty for gaps), float32-rounded like the workflow's files,
    in the frame the model was trained with, and (F,) the frames' reference headings (None in the world frame),
    their senses as the hulls give them (``featurise`` chooses them as the model's features did)."""
    settings = DescriptorSettings.from_config(model.descriptor, "model descriptor")
    descriptors, h0 = describe_sequence(seq, settings, n_basis=model.voxels["n_basis"])
    descriptors = [d.astype(np.float32).astype(np.float64) for d in descriptors]
    return descriptors, h0 if settings.frame == "body" else None


def featurise(model: PoseModel, descriptors: list, h0, name: str = "input") -> FrameFeatures:
    """Descriptors and reference headings from ``describe`` -> features (F, K) with NaN rows at gaps, counts
    (F,), the novelty scores and the headings with their senses chosen as the model's features chose them
    (``voxpose.features.heading_sense``), by the model's feature transformation (Eq. 5)."""
    n_a = DescriptorSettings.from_config(model.descriptor, "model descriptor").n_a
    return model.features.frame_features(descriptors, h0, n_a, name)


def regress(model: PoseModel, features: np.ndarray, valid: np.ndarray, h0: np.ndarray) -> np.ndarray:
    """Angles (F, 42) degrees from features, NaN rows where ``valid`` is false (Sections 2-3), the heading
    relative to the reference headings ``h0`` (F,) turned back (``descriptors.body_frame``; 0: world frame)."""
    angles = np.full((len(features), canon.N_ANGLES), np.nan)
    if valid.any():
        coords = model.mvrvm.predict(features[valid])
        relative = pose_encoding.decode(model.pca.inverse_transform(coords), model.heading)
        angles[valid] = pose_encoding.turn_heading(relative, h0[valid])
    return angles


def smooth_angles(angles: np.ndarray, valid: np.ndarray, sigma: float) -> np.ndarray:
    """Gaussian smoothing over time (sigma in frames) within each run of valid frames; gaps stay NaN."""
    if not sigma > 0:
        return angles.copy()
    out = angles.copy()
    edges = np.flatnonzero(np.diff(np.r_[0, valid.astype(np.int8), 0]))
    for start, stop in zip(edges[::2], edges[1::2], strict=True):
        run = unwrap_degrees(angles[start:stop], axis=0)
        out[start:stop] = gaussian_filter1d(run, sigma, axis=0, mode="nearest")
    return out


def predict_voxels(model: PoseModel, seq: VoxelSequence, *, frames=None, fps=None, true_angles=None,
                   smooth: float = 0.0, name: str = "input") -> Prediction:  # fmt: skip
    """Estimate every frame of a voxel sequence (module docstring); ``name`` names it in the warning logged
    when it lies far outside the training data."""
    if smooth < 0:
        raise VoxposeError(f"predict: smoothing must be >= 0 frames, got {smooth}")
    described = featurise(model, *describe(model, seq), name)
    features, counts, novelty = described.features, described.counts, described.novelty
    valid = counts > 0
    if not valid.any():
        raise VoxposeError("predict: no frame has a non-empty visual hull")
    gaps = np.flatnonzero(~valid)
    if gaps.size:
        log.warning("predict: %d of %d frames have an empty hull and no estimate (gaps): %s", gaps.size,
                    len(valid), gaps.tolist())  # fmt: skip
    angles = smooth_angles(regress(model, features, valid, described.heading_offsets()), valid, smooth)
    frames = np.arange(seq.n_frames) if frames is None else np.asarray(frames)
    if true_angles is not None and np.shape(true_angles) != angles.shape:
        raise VoxposeError(f"predict: true angles have shape {np.shape(true_angles)}, expected {angles.shape}")
    skeleton = subject_skeleton(model.skeleton, seq.h_sub)
    root = fit_roots(seq, angles, valid, skeleton, name=name)
    return Prediction(angles=angles, valid=valid, root=root, voxels=seq, frames=frames,
                      fps=float(fps or model.fps), true_angles=true_angles, smooth=float(smooth),
                      novelty=novelty, skeleton=skeleton)  # fmt: skip


def bvh_channels(prediction: Prediction) -> tuple[np.ndarray, np.ndarray]:
    """(angles, world root positions) for the BVH: gap frames at rest, at their nearest earlier valid root."""
    valid = prediction.valid
    source = np.maximum.accumulate(np.where(valid, np.arange(len(valid)), -1))
    source[source < 0] = np.flatnonzero(valid)[0]  # leading gaps: the first frame with an estimate
    angles = np.where(valid[:, None], prediction.angles, 0.0)
    return angles, prediction.world_root()[source]
