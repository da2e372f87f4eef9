"""Eq. 5 features and the K-means soft-vote baseline against brute-force loops over frames and descriptors."""

import numpy as np
import pytest
from scipy.special import logsumexp
from scipy.stats import multivariate_normal

from voxpose.errors import NotFittedError, VoxposeError
from voxpose.features.frame import SoftVoteRule, kmeans_features, mppca_features
from voxpose.features.kmeans import KMeans, group_sums
from voxpose.features.mppca import MPPCA


def descriptors_of_frames(seed, n_frames=6, d=5):
    """Descriptors of ``n_frames`` frames (frame 2 left empty), shuffled, with their frame index."""
    rng = np.random.default_rng(seed)
    sizes = rng.integers(5, 30, size=n_frames)
    sizes[2] = 0
    frame_index = np.repeat(np.arange(n_frames), sizes)
    X = rng.normal(size=(frame_index.size, d)) + 3.0 * rng.integers(0, 3, size=(frame_index.size, 1))
    order = rng.permutation(frame_index.size)
    return X[order], frame_index[order], sizes


@pytest.fixture(scope="module")
def mppca_model():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(600, 5)) + 3.0 * rng.integers(0, 3, size=(600, 1))
    return MPPCA(4, n_latent=2, max_iter=20, random_state=0).fit(X)


def test_mppca_features_equal_brute_force_eq5(mppca_model, caplog):
    X, frame_index, sizes = descriptors_of_frames(1)
    with caplog.at_level("WARNING", logger="voxpose.features.frame"):
        features, counts = mppca_features(mppca_model, X, frame_index, 6, chunk_size=7)
    m = mppca_model
    components = [
        multivariate_normal(mu, W @ W.T + s * np.eye(5))
        for mu, W, s in zip(m.means_, m.components_, m.noise_variance_, strict=True)
    ]
    for f in range(6):
        rows = X[frame_index == f]
        if len(rows) == 0:
            continue
        total = np.zeros(4)
        for t in rows:  # Eq. 5, one descriptor at a time
            log_joint = np.log(m.weights_) + np.array([c.logpdf(t) for c in components])
            total += np.exp(log_joint - logsumexp(log_joint))
        np.testing.assert_allclose(features[f], total / len(rows), atol=1e-12)
    np.testing.assert_array_equal(counts, sizes)
    assert np.isnan(features[2]).all() and counts[2] == 0
    np.testing.assert_allclose(np.delete(features, 2, axis=0).sum(axis=1), 1.0, atol=1e-12)
    assert "1 of 6 frames have no descriptors (first: frame 2)" in caplog.text


def brute_force_votes(t, centres, n_nearest, bandwidth):
    distances = np.array([np.sum((t - c) ** 2) for c in centres])
    nearest = np.argsort(distances)[:n_nearest]
    weights = np.exp(-distances[nearest] / (2 * bandwidth**2))
    votes = np.zeros(len(centres))
    votes[nearest] = weights / weights.sum()
    return votes


@pytest.mark.parametrize("n_nearest", [1, 3, 5])
def test_kmeans_features_equal_brute_force_soft_votes(n_nearest):
    X, frame_index, sizes = descriptors_of_frames(2)
    centres = KMeans(5, random_state=0).fit(X).cluster_centers_
    rule = SoftVoteRule(n_nearest=n_nearest, bandwidth=1.5)
    features, counts = kmeans_features(centres, X, frame_index, 6, rule=rule, chunk_size=4)
    for f in range(6):
        rows = X[frame_index == f]
        if len(rows):
            expected = np.mean([brute_force_votes(t, centres, n_nearest, 1.5) for t in rows], axis=0)
            np.testing.assert_allclose(features[f], expected, atol=1e-12)
    np.testing.assert_array_equal(counts, sizes)
    assert np.isnan(features[2]).all()
    np.testing.assert_allclose(np.delete(features, 2, axis=0).sum(axis=1), 1.0, atol=1e-12)
    if n_nearest == 1:  # hard vector quantisation: the normalised histogram of nearest-centre labels
        labels = np.argmin(((X[:, None, :] - centres[None]) ** 2).sum(axis=2), axis=1)
        hist = np.array([np.bincount(labels[frame_index == f], minlength=5) / sizes[f] for f in (0, 1, 3)])
        np.testing.assert_allclose(features[[0, 1, 3]], hist, atol=1e-12)


@pytest.mark.parametrize("n_nearest", [1, 3])
def test_frame_sums_are_the_dense_votes_summed_by_frame_bit_for_bit(n_nearest):
    """``SoftVoteRule.frame_sums`` adds each row's few votes into its frame's bins: the same bits as summing the
    dense (n, K) vote rows per frame with ``group_sums``, on rows of many magnitudes in shuffled frames."""
    rng = np.random.default_rng(n_nearest)
    centres = rng.normal(size=(7, 4))
    X = rng.normal(size=(3000, 4)) * np.exp(rng.normal(size=(3000, 1)) * 0.5)
    frame_index = rng.integers(0, 11, 3000)
    frame_index[frame_index == 4] = 5  # a frame without rows
    rule = SoftVoteRule(n_nearest=n_nearest, bandwidth=2.0)
    nearest, weights = rule.nearest_weights(X, centres)
    dense = np.zeros((3000, 7))
    np.put_along_axis(dense, nearest, weights, axis=1)
    got = rule.frame_sums(X, centres, frame_index, 11)
    np.testing.assert_array_equal(got, group_sums(frame_index, dense, 11))
    assert not got[4].any() and got.sum() == pytest.approx(3000.0)
    for f in (0, 7):  # and the brute-force votes summed
        expected = sum(brute_force_votes(t, centres, n_nearest, 2.0) for t in X[frame_index == f])
        np.testing.assert_allclose(got[f], expected, rtol=1e-12)


def test_soft_vote_width_is_the_mean_nearest_centre_distance():
    X, _, _ = descriptors_of_frames(3)
    centres = KMeans(4, random_state=0).fit(X).cluster_centers_
    nearest = [min(np.linalg.norm(t - c) for c in centres) for t in X]
    rule = SoftVoteRule.from_training(centres, X, n_nearest=2, bandwidth_scale=0.5, chunk_size=9)
    assert rule.n_nearest == 2
    assert rule.bandwidth == pytest.approx(0.5 * np.mean(nearest), rel=1e-12)


def test_bad_frame_input_raises(mppca_model):
    X, frame_index, _ = descriptors_of_frames(4)
    centres = X[:5]
    rule = SoftVoteRule(2, 1.0)
    cases = [
        ((X, frame_index[:-1], 6), "one entry per descriptor"),
        ((X, frame_index.astype(float), 6), "integers"),
        ((X, np.where(frame_index == 4, 9, frame_index), 6), "outside the 6 frames"),
        ((X, frame_index - 1, 6), "outside the 6 frames"),
        ((X, frame_index, 0), "n_frames"),
        ((X[:, :4], frame_index, 6), "expected 5 columns, got 4"),
        (
            (np.where(np.arange(X.size).reshape(X.shape) == 7, np.nan, X), frame_index, 6),
            "row 1 contains NaN",
        ),
    ]
    for args, message in cases:
        with pytest.raises(VoxposeError, match=message):
            mppca_features(mppca_model, *args)
        with pytest.raises(VoxposeError, match=message):
            kmeans_features(centres, *args, rule=rule)
    with pytest.raises(NotFittedError, match="MPPCA is not fitted"):
        mppca_features(MPPCA(2), X, frame_index, 6)
    with pytest.raises(VoxposeError, match="only 5"):
        kmeans_features(centres, X, frame_index, 6, rule=SoftVoteRule(6, 1.0))
    for n_nearest, bandwidth, message in [
        (0, 1.0, "n_nearest"),
        (2.5, 1.0, "n_nearest"),
        (2, 0.0, "bandwidth"),
    ]:
        with pytest.raises(VoxposeError, match=message):
            SoftVoteRule(n_nearest, bandwidth)
    with pytest.raises(VoxposeError, match="coincides"):
        SoftVoteRule.from_training(centres, centres)
