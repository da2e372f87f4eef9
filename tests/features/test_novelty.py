"""The out-of-range warning (features/novelty.py): scores against a brute-force mean log-density, the
documented threshold, and planted in- and out-of-distribution motions."""

import logging

import numpy as np
import pytest

from voxpose.features.model import FeatureModel
from voxpose.features.mppca import MPPCA
from voxpose.features.novelty import DESCRIPTORS_PER_FRAME, NoveltyRange, evenly_spaced, frame_scores

CFG = {"n_components": 3, "n_latent": 2, "max_iter": 100, "tol": 1e-6, "fit_subsample": None, "kmeans_neighbours": 2}
CENTRES = np.array([[0.0, 0.0, 0.0, 0.0], [4.0, 0.0, 4.0, 0.0], [0.0, 4.0, 0.0, 4.0]])


def planted_frames(rng, n_frames, shift=0.0, per_frame=30):
    """Frames of descriptors drawn around the three planted centres, moved by ``shift`` in every coordinate."""
    return [CENTRES[rng.integers(3, size=per_frame)] + rng.normal(scale=0.5, size=(per_frame, 4)) + shift
            for _ in range(n_frames)]  # fmt: skip


@pytest.fixture(scope="module")
def fitted():
    rng = np.random.default_rng(3)
    train = planted_frames(rng, 120)
    return FeatureModel.fit("mppca", np.concatenate(train), CFG, seed=2).with_novelty_range(train), train


@pytest.mark.parametrize("n, k", [(5, 20), (20, 20), (21, 20), (1000, 7)])
def test_evenly_spaced_indices_are_distinct_increasing_and_start_at_zero(n, k):
    idx = evenly_spaced(n, k)
    assert len(idx) == min(n, k) and idx[0] == 0 and idx[-1] < n
    assert np.all(np.diff(idx) > 0)


def test_frame_scores_equal_the_mean_log_density_of_the_sampled_descriptors():
    rng = np.random.default_rng(0)
    mppca = MPPCA(2, n_latent=1, random_state=0).fit(rng.normal(size=(300, 3)))
    frames = [rng.normal(size=(n, 3)) for n in (1, 20, 45, 0, 7)]
    expected = [np.mean([mppca.score_samples(d[i : i + 1])[0] for i in evenly_spaced(len(d), DESCRIPTORS_PER_FRAME)])
                if len(d) else np.nan for d in frames]  # fmt: skip
    np.testing.assert_allclose(frame_scores(mppca, frames), expected, rtol=1e-12)


def test_threshold_is_as_far_below_the_first_percentile_as_that_is_below_the_median(fitted):
    model, train = fitted
    scores = frame_scores(model.estimator, train)  # 120 frames: all of them are measured
    low, median = np.percentile(scores, [1, 50])
    rng = NoveltyRange(**model.meta["novelty"])
    assert rng.n_frames == 120
    np.testing.assert_allclose([rng.low, rng.median, rng.threshold], [low, median, 2 * low - median])


def test_new_frames_of_the_training_distribution_are_in_range(fitted, caplog):
    model, _ = fitted
    scores, summary = model.novelty("same-body", planted_frames(np.random.default_rng(9), 60))
    assert not summary["warned"] and summary["out_of_range"] < 0.05
    assert np.isfinite(scores).all() and "same-body" not in caplog.text


def test_frames_far_from_training_are_out_of_range_and_logged(fitted, caplog):
    model, _ = fitted
    with caplog.at_level(logging.WARNING):
        _, summary = model.novelty("other-body", planted_frames(np.random.default_rng(9), 60, shift=3.0))
    assert summary["warned"] and summary["out_of_range"] == 1.0
    assert "other-body" in caplog.text and "outside the training data" in caplog.text


def test_the_range_survives_the_model_file_and_kmeans_has_none(fitted, tmp_path):
    model, train = fitted
    model.save(tmp_path / "m.h5")
    assert FeatureModel.load(tmp_path / "m.h5").meta["novelty"] == model.meta["novelty"]
    kmeans = FeatureModel.fit("kmeans", np.concatenate(train), CFG, seed=2).with_novelty_range(train)
    assert "novelty" not in kmeans.meta and kmeans.novelty("x", train) == (None, None)
