"""The body frame's heading sense chosen by the feature model's density (features/heading_sense.py): the turn
about against shape contexts of a body turned by brute force, planted back-facing frames found by a fitted
MPPCA and K-means, and the training frames turned to their true heading."""

import json
from dataclasses import replace

import numpy as np
import pytest

from tests.helpers import one_line_error, run_voxpose, tpose
from voxpose.descriptors.file import write_descriptors
from voxpose.descriptors.shape_context import shape_contexts
from voxpose.errors import VoxposeError
from voxpose.features.heading_sense import choose_senses, true_turns, turn_about
from voxpose.features.model import FeatureModel, subsample
from voxpose.features.novelty import evenly_spaced
from voxpose.features.training_set import read_training_set
from voxpose.motion import canon
from voxpose.motion.data import write_motion

N_R, N_E, N_A = 2, 2, 6
CFG = {"n_components": 3, "n_latent": 2, "max_iter": 300, "tol": 1e-6, "fit_subsample": None, "kmeans_neighbours": 2,
       "heading_sense": "density"}  # fmt: skip
PROFILE = np.array([6.0, 4.0, 2.0, 1.0, 1.0, 2.0])
"""Mean votes per azimuth sector of a planted 'front' descriptor: turned about it reads [1, 1, 2, 6, 4, 2]."""


@pytest.mark.parametrize("soft", [True, False])
@pytest.mark.parametrize("n_a", [10, 4])
def test_turn_about_is_the_body_described_turned_by_180_degrees(soft, n_a):
    rng = np.random.default_rng(1)
    points = rng.uniform([-0.3, 0.0, -0.2], [0.3, 1.7, 0.2], size=(400, 3))
    centres = points[:25]
    params = {"n_r": 3, "n_e": 4, "n_a": n_a, "soft": soft}
    turned = points * np.array([-1.0, 1.0, -1.0])  # 180 degrees about the vertical through the origin
    direct = shape_contexts(turned, centres * np.array([-1.0, 1.0, -1.0]), l_res=0.02, h_sub=1.7, **params)
    described = shape_contexts(points, centres, l_res=0.02, h_sub=1.7, **params)
    assert np.abs(turn_about(described, n_a) - direct).max() < 1e-12
    assert np.abs(described - direct).max() > 0.1  # the body is not symmetric: the turn matters


def test_turning_twice_is_the_identity_and_an_odd_sector_count_is_refused():
    d = np.random.default_rng(0).random((5, N_R * N_E * N_A))
    assert np.array_equal(turn_about(turn_about(d, N_A), N_A), d)
    with pytest.raises(VoxposeError, match="n_a = 5 is odd"):
        turn_about(np.zeros((2, 20)), 5)


def test_true_turns_are_the_frames_more_than_90_degrees_off():
    h0 = [0.0, 170.0, 350.0, 10.0, 300.0]
    truth = [10.0, -20.0, 200.0, 99.0, 30.0]  # off by 10, 170, 150, 89, 90 degrees (wrapped)
    assert true_turns(h0, truth).tolist() == [False, True, True, False, False]


def front_frames(rng, n_frames, per_frame=20):
    """Descriptors of bodies seen from the front: every ring's azimuth votes drawn around ``PROFILE``."""
    shape = (per_frame, N_R * N_E, N_A)
    return [rng.gamma(4.0, PROFILE / 4.0, size=shape).reshape(per_frame, -1) for _ in range(n_frames)]


@pytest.mark.parametrize("method", ["mppca", "kmeans"])
def test_the_density_finds_the_frames_seen_from_the_back(method):
    rng = np.random.default_rng(2)
    model = FeatureModel.fit(method, np.concatenate(front_frames(rng, 60)), CFG, seed=0)
    frames = front_frames(rng, 40)
    frames[25] = np.zeros((0, N_R * N_E * N_A))  # a gap
    truth = 30.0 + 2.0 * np.arange(40)  # the true heading, turning slowly
    back = (np.arange(40) >= 8) & (np.arange(40) < 20) | (np.arange(40) == 33)  # a run and a lone frame
    h0 = np.where(back, truth + 180.0, truth) % 360.0
    seen = [turn_about(d, N_A) if b and len(d) else d for d, b in zip(frames, back, strict=True)]
    got_frames, got_h0 = model.orient(seen, h0, N_A)
    assert np.abs(((got_h0 - truth + 180.0) % 360.0) - 180.0).max() < 1e-9
    assert all(np.array_equal(g, d) for g, d in zip(got_frames, frames, strict=True))
    shape_model = FeatureModel.fit(method, np.concatenate(front_frames(rng, 60)), CFG | {"heading_sense": "shape"}, 0)
    assert shape_model.orient(seen, h0, N_A)[1] is h0  # shape: the hull's own choice stands
    got_frames, got_h0 = model.orient(seen, None, N_A)
    assert got_frames is seen and got_h0 is None  # world frame: nothing to choose


@pytest.mark.parametrize("method, sense", [("mppca", "density"), ("mppca", "shape"), ("kmeans", "density")])
def test_frame_features_are_orient_then_transform_then_novelty(method, sense):
    """The fused evaluation (MPPCA with the density's senses: each descriptor's posterior and density from one
    log joint, the turned frames evaluated again) gives what the three steps give one after the other, with
    frames turned about, a gap, frames of varying size; the other methods run the three steps."""
    rng = np.random.default_rng(4)
    train = front_frames(rng, 60, per_frame=30)
    model = FeatureModel.fit(method, np.concatenate(train), CFG | {"heading_sense": sense}, seed=0)
    model = model.with_novelty_range(train)
    frames = [d[: 10 + 7 * (f % 5)] for f, d in enumerate(front_frames(rng, 40, per_frame=50))]
    frames[25] = np.zeros((0, N_R * N_E * N_A))
    back = (np.arange(40) >= 8) & (np.arange(40) < 20) | (np.arange(40) == 33)
    seen = [turn_about(d, N_A) if b and len(d) else d for d, b in zip(frames, back, strict=True)]
    h0 = (30.0 + 2.0 * np.arange(40) + 180.0 * back) % 360.0
    fused = model.frame_features(seen, h0, N_A, "seq")
    oriented, chosen = model.orient(seen, h0, N_A, "seq")
    features, counts = model.transform_frames(oriented)
    scores, summary = model.novelty("seq", oriented)
    if sense == "density":
        assert true_turns(h0, chosen).sum() == back.sum()  # the planted turns are found and undone
    assert all(np.array_equal(a, b) for a, b in zip(fused.frames, oriented, strict=True))
    np.testing.assert_array_equal(fused.h0, chosen)
    np.testing.assert_array_equal(fused.counts, counts)
    np.testing.assert_allclose(fused.features, features, rtol=0, atol=1e-12)
    if method == "kmeans":
        assert fused.scores is None and fused.novelty is None and scores is None
        return
    np.testing.assert_allclose(fused.scores, scores, rtol=1e-12)
    assert np.isnan(fused.scores[25]) and fused.novelty.keys() == summary.keys()
    assert fused.novelty == pytest.approx(summary, rel=1e-12)
    assert model.frame_features(seen, None, N_A).h0 is None  # world frame: nothing to choose


def test_a_sequence_keeps_a_lone_frame_against_its_neighbours():
    """Per-frame evidence that points backwards on one frame of a run is overruled by continuity; a long run is
    followed (planted log densities: the evidence is the frame's first bin minus its turned first bin)."""
    def log_density(rows):
        return rows[:, 0]

    n = 30
    frames = [np.tile(np.r_[1.0, 0, 0, 0, 0, 0], (3, 1)) for _ in range(n)]
    frames[5] = turn_about(frames[5], N_A)  # one frame whose evidence points backwards
    for k in range(15, 30):
        frames[k] = turn_about(frames[k], N_A)  # a long run of frames seen from the back
    h0 = np.full(n, 45.0)
    got_frames, got_h0 = choose_senses(log_density, frames, h0, N_A)
    assert got_h0[5] == 45.0 and np.array_equal(got_frames[5], frames[5])
    assert np.allclose(got_h0[15:], 225.0) and all(g[0, 0] == 1.0 for g in got_frames[15:])


@pytest.fixture
def training_files(tmp_path):
    """Two descriptor files with reference headings and their motion files (true headings planted)."""
    rng = np.random.default_rng(3)
    paths, motions, frames, turns = [], [], [], []
    for k, n in enumerate([6, 4]):
        desc = front_frames(rng, n, per_frame=5)
        truth = rng.uniform(-180, 180, n)
        turn = rng.random(n) < 0.5
        h0 = np.where(turn, truth + 180.0, truth)
        path = tmp_path / f"m{k}.h5"
        meta = {"motion": f"m{k}", "params": {"n_r": N_R, "n_e": N_E, "n_a": N_A, "frame": "body"}}
        write_descriptors(path, desc, [np.zeros((5, 3), np.int32)] * n, meta, reference_heading=h0)
        angles = np.zeros((n, canon.N_ANGLES))
        angles[:, canon.ANGLE_NAMES.index("root_y")] = truth
        motion = replace(tpose(n), name=f"m{k}", angles=angles)
        write_motion(tmp_path / f"m{k}_motion.h5", motion)
        paths.append(path)
        motions.append(tmp_path / f"m{k}_motion.h5")
        frames += [d.astype(np.float32).astype(np.float64) for d in desc]
        turns.append(turn)
    return paths, motions, frames, turns


@pytest.mark.parametrize(("n", "n_frames"), [(None, 500), (9, 5)])
def test_training_frames_are_turned_to_their_true_heading(training_files, n, n_frames):
    """The drawn rows and the novelty frames are those of the whole set with its frames turned first: all of them,
    and 9 drawn rows with 5 frames (drawn and picked from turned and unturned frames alike)."""
    paths, _, frames, turns = training_files
    got = read_training_set(paths, n, seed=0, n_frames=n_frames, turns=turns, n_a=N_A)
    expected = [turn_about(d, N_A) if t else d for d, t in zip(frames, np.concatenate(turns), strict=True)]
    assert np.array_equal(got.rows, subsample(np.concatenate(expected), n, 0))
    assert not np.array_equal(got.rows, subsample(np.concatenate(frames), n, 0))  # some drawn rows were turned
    picked = evenly_spaced(len(expected), n_frames)
    assert 0 < np.concatenate(turns)[picked].sum() < len(picked)
    assert len(got.frames) == len(picked)
    assert all(np.array_equal(a, expected[i]) for a, i in zip(got.frames, picked, strict=True))


def test_fit_features_turns_the_training_frames_and_names_mismatched_files(training_files, tmp_path):
    paths, motions, _, turns = training_files
    params = json.dumps(CFG)
    out = tmp_path / "model.h5"
    fit = ("fit-features", "--method", "mppca", "--params", params)
    proc = run_voxpose(*fit, "--motions", *motions, "-o", out, *paths)
    assert proc.returncode == 0, proc.stderr
    assert FeatureModel.load(out).meta["turned_training_frames"] == sum(int(t.sum()) for t in turns)
    bad = tmp_path / "bad.h5"
    one_line_error(run_voxpose(*fit, "--motions", *motions[::-1], "-o", bad, *paths), str(motions[1]), str(paths[0]))
    one_line_error(run_voxpose(*fit, "-o", bad, *paths), "--motions")
    assert not bad.exists()
