"""The root fit against known geometry: a generated body carved at a known root is found again within a voxel
from its angles, also in a long dress that pulls the hull's centroid far down; gaps give NaN."""

import logging

import numpy as np
import pytest

from tests.helpers import without_frame
from voxpose import kernels
from voxpose.apply.posed_body import posed_body, skeleton_height, subject_skeleton
from voxpose.apply.root_fit import fit_roots, hull_centroids
from voxpose.io.bvh import write_bvh
from voxpose.motion.generate import generate_motion
from voxpose.motion.load import load_motion
from voxpose.motion.output_skeleton import OutputSkeleton
from voxpose.voxels.cameras import circular_rig
from voxpose.voxels.render import render_silhouettes
from voxpose.voxels.sequence import VoxelSequence
from voxpose.voxels.voxelize import subject_shifts, voxelize_silhouettes

N_FRAMES = 50


@pytest.fixture(scope="module")
def carved(tmp_path_factory):
    """A generated walk's body model (its own skeleton, its angles) at its own root, carved by the default rig
    at h_sub / 60; -> (voxels, angles, skeleton, true root in the voxels' coordinates)."""
    path = tmp_path_factory.mktemp("root") / "walk_gen_00.bvh"
    write_bvh(generate_motion("walk", seed=3, n_frames=N_FRAMES, height=1.7), path)
    motion = load_motion(path)
    skeleton = OutputSkeleton.from_motions([motion])
    rig = circular_rig()
    shifts = subject_shifts(motion, rig)
    body = posed_body(motion.angles, skeleton, motion.positions[:, 0]).translated(shifts)
    silhouettes = (render_silhouettes(body.frame(f), rig) for f in range(N_FRAMES))
    seq = voxelize_silhouettes(silhouettes, rig, shifts=shifts, progress_every=0)
    return seq, motion.angles, skeleton, motion.positions[:, 0] + shifts


def with_voxels(seq: VoxelSequence, frames) -> VoxelSequence:
    """A sequence of the given frames' voxels (surface and basis voxels left empty: the fit does not use them)."""
    counts = [len(v) for v in frames]
    n = len(frames)
    return VoxelSequence(
        l_res=seq.l_res, h_sub=seq.h_sub, h_sub_frame=0, ijk=np.concatenate(frames).astype(np.int32),
        offsets=np.r_[0, np.cumsum(counts)], surface=np.zeros(sum(counts), bool), basis=np.zeros(0, np.int32),
        basis_offsets=np.zeros(n + 1, np.int64), empty=np.array(counts) == 0, shifts=np.zeros((n, 3)),
    )  # fmt: skip


def skirt(root, floor, l_res):
    """Voxels of a solid truncated cone (a long dress) around the root's vertical: from 5 cm below the root,
    0.18 m wide, down to 15 cm above the floor, 0.40 m wide."""
    top, bottom = root[1] - 0.05, floor + 0.15
    lo = np.floor((np.array([root[0] - 0.45, bottom, root[2] - 0.45])) / l_res).astype(int)
    hi = np.ceil((np.array([root[0] + 0.45, top, root[2] + 0.45])) / l_res).astype(int)
    ijk = np.argwhere(np.ones(hi - lo, dtype=bool)) + lo
    x = (ijk + 0.5) * l_res
    radius = 0.18 + (top - x[:, 1]) / (top - bottom) * (0.40 - 0.18)
    inside = (x[:, 1] >= bottom) & (x[:, 1] <= top) & (np.hypot(x[:, 0] - root[0], x[:, 2] - root[2]) <= radius)
    return ijk[inside]


def test_the_true_angles_put_the_root_within_a_voxel_of_the_truth(carved):
    seq, angles, skeleton, truth = carved
    roots = fit_roots(seq, angles, np.ones(N_FRAMES, bool), skeleton)
    error = np.linalg.norm(roots - truth, axis=1) / seq.l_res
    assert error.max() < 1.0, error.max()
    centroid = np.linalg.norm(hull_centroids(seq) - truth, axis=1) / seq.l_res
    assert centroid.max() > 2.0  # the centroid is not the root even without a dress
    # the same numbers frame by frame whatever the other frames fitted with it (every other frame)
    alternate = np.arange(N_FRAMES) % 2 == 0
    again = fit_roots(seq, angles, alternate, skeleton)
    np.testing.assert_allclose(again[alternate], roots[alternate], atol=1e-9)
    assert np.isnan(again[~alternate]).all()


def test_a_long_dress_moves_the_centroid_not_the_fitted_root(carved):
    seq, angles, skeleton, truth = carved
    frames = range(0, N_FRAMES, 5)
    dressed = []
    for f in frames:
        hull = seq.frame(f)[0]
        floor = hull[:, 1].min() * seq.l_res
        dressed.append(np.unique(np.concatenate([hull, skirt(truth[f], floor, seq.l_res)]), axis=0))
    dressed = with_voxels(seq, dressed)
    truth = truth[list(frames)]
    centroid = np.linalg.norm(hull_centroids(dressed) - truth, axis=1)
    roots = fit_roots(dressed, angles[list(frames)], np.ones(len(frames), bool), skeleton)
    error = np.linalg.norm(roots - truth, axis=1)
    assert centroid.min() > 0.15, centroid  # metres
    assert error.max() < 0.02, error


def test_gaps_and_frames_without_estimate_are_nan(carved, caplog):
    seq, angles, skeleton, truth = carved
    gappy = without_frame(seq, 7)
    valid = np.ones(N_FRAMES, bool)
    valid[11] = False
    with caplog.at_level(logging.INFO, logger="voxpose.apply.root_fit"):
        roots = fit_roots(gappy, angles, valid, skeleton, progress_every=20, name="gappy")
    assert np.isnan(roots[[7, 11]]).all()
    kept = np.setdiff1d(np.arange(N_FRAMES), [7, 11])
    assert np.isfinite(roots[kept]).all()
    assert np.linalg.norm(roots[kept] - truth[kept], axis=1).max() < seq.l_res
    lines = [r.getMessage() for r in caplog.records if r.name == "voxpose.apply.root_fit"]
    assert lines == ["root fit gappy: 32/48 frames", "root fit gappy: 48/48 frames"]
    empty = with_voxels(seq, [np.zeros((0, 3), int)] * 2)
    assert np.isnan(fit_roots(empty, angles[:2], np.ones(2, bool), skeleton)).all()


def test_a_model_skeleton_of_another_size_is_scaled_to_the_subject(carved):
    """The model's output skeleton has its training subjects' size; scaled to h_sub (the subject's measured
    height) it puts the root of a subject 15 % taller within a voxel, unscaled it does not."""
    seq, angles, skeleton, truth = carved
    small = skeleton.scaled(1 / 1.15)
    assert skeleton_height(small) == pytest.approx(skeleton_height(skeleton) / 1.15)
    valid = np.ones(N_FRAMES, bool)
    scaled = subject_skeleton(small, seq.h_sub)
    assert skeleton_height(scaled) == pytest.approx(seq.h_sub)
    error = {name: np.linalg.norm(fit_roots(seq, angles, valid, s) - truth, axis=1) / seq.l_res
             for name, s in (("scaled", scaled), ("unscaled", small))}  # fmt: skip
    assert error["scaled"].max() < 1.0
    assert error["unscaled"].mean() > 1.5  # measured 1.86 voxels (5.3 cm) mean, 0.07 scaled


@pytest.mark.skipif(not kernels.numba_available(), reason="numba is not installed: numpy path only")
def test_the_compiled_climb_fits_the_numpy_paths_roots(carved, monkeypatch):
    """voxpose.apply.root_fit_kernels: the same integer overlaps, so the same roots bit for bit, also for a dress
    and for angles off by a few degrees (longer climbs)."""
    seq, angles, skeleton, _ = carved
    noisy = angles + np.random.default_rng(0).normal(scale=4.0, size=angles.shape)
    frames = range(0, N_FRAMES, 7)
    centres = hull_centroids(seq)[::7]
    pairs = zip(frames, centres, strict=True)
    dressed = with_voxels(seq, [np.vstack([seq.frame(f)[0], skirt(c, 0.0, seq.l_res)]) for f, c in pairs])
    cases = [(seq, angles), (seq, noisy), (dressed, angles[::7])]
    fitted = {}
    for kind in ("numba", "numpy"):
        monkeypatch.setenv(kernels.ENV, kind)
        fitted[kind] = [fit_roots(s, a, np.ones(len(a), bool), skeleton) for s, a in cases]
    for fast, slow in zip(fitted["numba"], fitted["numpy"], strict=True):
        assert np.isfinite(slow).all()
        np.testing.assert_array_equal(fast, slow)
