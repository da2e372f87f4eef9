"""k-means: planted centres, brute-force labels and inertia, determinism, chunking, empty clusters,
bad input."""

import warnings

import numpy as np
import pytest

import voxpose.features.kmeans as kmeans_module
from voxpose.errors import ConvergenceWarning, NotFittedError, VoxposeError
from voxpose.features.kmeans import (
    KMeans,
    group_sums,
    kmeans_plus_plus,
    mean_feature_variance,
    nearest_centres,
)


def planted_blobs(seed, n_per=200, spread=0.3):
    """Five well-separated isotropic blobs in 3-D; returns (X, true centres)."""
    rng = np.random.default_rng(seed)
    centres = np.array([[0, 0, 0], [10, 0, 0], [0, 10, 0], [0, 0, 10], [10, 10, 10]], dtype=float)
    X = np.concatenate([c + spread * rng.standard_normal((n_per, 3)) for c in centres])
    return X[rng.permutation(len(X))], centres


def brute_force_sqdist(X, centres):
    return np.array([[float(((x - c) ** 2).sum()) for c in centres] for x in X])


def test_helpers_match_brute_force():
    rng = np.random.default_rng(1)
    X, centres = rng.normal(size=(30, 4)), rng.normal(size=(6, 4))
    reference = brute_force_sqdist(X, centres)
    labels, sqdist = nearest_centres(X, centres, chunk_size=7)
    np.testing.assert_array_equal(labels, reference.argmin(axis=1))
    np.testing.assert_allclose(sqdist, reference.min(axis=1), rtol=1e-12)
    index = rng.integers(0, 5, size=30)
    expected = np.array([X[index == g].sum(axis=0) for g in range(5)])
    np.testing.assert_allclose(group_sums(index, X, 5), expected, rtol=1e-12, atol=1e-12)
    assert mean_feature_variance(X, chunk_size=7) == pytest.approx(np.var(X, axis=0).mean(), rel=1e-12)


def test_recovers_planted_centres_and_reports_consistent_state():
    X, truth = planted_blobs(0)
    model = KMeans(5, random_state=3, chunk_size=64).fit(X)
    found = model.cluster_centers_
    match = brute_force_sqdist(truth, found).argmin(axis=1)
    assert sorted(match) == list(range(5))
    np.testing.assert_allclose(found[match], truth, atol=0.1)
    reference = brute_force_sqdist(X, found)
    np.testing.assert_array_equal(model.labels_, reference.argmin(axis=1))
    assert model.inertia_ == pytest.approx(reference.min(axis=1).sum(), rel=1e-10)
    np.testing.assert_array_equal(model.predict(X), model.labels_)
    assert model.converged_


def test_same_seed_same_result_and_chunking_does_not_matter():
    X, _ = planted_blobs(2, spread=3.0)  # overlapping blobs: the answer depends on the seeding
    a = KMeans(5, random_state=7, chunk_size=13).fit(X)
    b = KMeans(5, random_state=7, chunk_size=13).fit(X)
    c = KMeans(5, random_state=7, chunk_size=len(X)).fit(X)
    np.testing.assert_array_equal(a.cluster_centers_, b.cluster_centers_)
    np.testing.assert_allclose(a.cluster_centers_, c.cluster_centers_, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(a.labels_, c.labels_)


def test_kmeans_plus_plus_draws_distinct_rows():
    X, _ = planted_blobs(4)
    centres = kmeans_plus_plus(X, 5, np.random.default_rng(0), chunk_size=50)
    rows = [int(np.flatnonzero((X == c).all(axis=1))[0]) for c in centres]
    assert len(set(rows)) == 5
    # D^2 sampling on far-apart blobs puts one seed in each blob
    assert len(set(np.argmin(brute_force_sqdist(centres, planted_blobs(4)[1]), axis=1))) == 5


def test_empty_cluster_is_moved_to_the_farthest_row(monkeypatch, caplog):
    X, truth = planted_blobs(5)

    def far_seeds(X, n_clusters, rng, chunk_size):
        seeds = truth.copy()
        seeds[4] = 1000.0  # no row is nearest to this seed: it empties at the first iteration
        return seeds

    monkeypatch.setattr(kmeans_module, "kmeans_plus_plus", far_seeds)
    with caplog.at_level("INFO", logger="voxpose.features.kmeans"):
        model = KMeans(5, random_state=0).fit(X)
    assert "moved 1 empty clusters" in caplog.text
    assert np.bincount(model.labels_, minlength=5).min() > 0
    match = brute_force_sqdist(truth, model.cluster_centers_).argmin(axis=1)
    assert sorted(match) == list(range(5))
    np.testing.assert_allclose(model.cluster_centers_[match], truth, atol=0.1)


@pytest.mark.parametrize(
    ("X", "kwargs", "message"),
    [
        (np.array([[0.0, 1.0], [np.nan, 2.0], [3.0, 4.0]]), {"n_clusters": 2}, "row 1"),
        (np.array([[0.0, 1.0], [1.0, np.inf], [3.0, 4.0]]), {"n_clusters": 2}, "row 1"),
        (np.zeros(5), {"n_clusters": 2}, "2-D"),
        (np.arange(6.0).reshape(3, 2), {"n_clusters": 4}, "n_clusters"),
        (np.arange(6.0).reshape(3, 2), {"n_clusters": 2, "chunk_size": 0}, "chunk_size"),
        (np.arange(6.0).reshape(3, 2), {"n_clusters": 2, "max_iter": 0}, "max_iter"),
        (np.ones((4, 2)), {"n_clusters": 2}, "distinct rows"),
    ],
)
def test_bad_input_raises(X, kwargs, message):
    with pytest.raises(VoxposeError, match=message):
        KMeans(random_state=0, **kwargs).fit(X)


def test_predict_checks_fit_and_dimension():
    for use in (lambda: KMeans(2).predict(np.zeros((2, 3))), KMeans(2).to_arrays):
        with pytest.raises(NotFittedError, match=r"^KMeans is not fitted: call fit first$"):
            use()
    model = KMeans(2, random_state=0).fit(np.arange(12.0).reshape(4, 3))
    with pytest.raises(VoxposeError, match="k-means input: expected 3 columns, got 4"):
        model.predict(np.zeros((2, 4)))


def test_restored_model_predicts_exactly_like_the_fitted_one():
    X, _ = planted_blobs(4, spread=2.0)
    model = KMeans(5, random_state=1).fit(X)
    restored = KMeans.from_arrays(*model.to_arrays())
    np.testing.assert_array_equal(restored.predict(X), model.predict(X))
    assert restored.n_clusters == 5
    assert (restored.inertia_, restored.n_iter_, restored.converged_) == (model.inertia_, model.n_iter_, True)


def test_a_fit_stopped_by_max_iter_warns():
    X, _ = planted_blobs(4, spread=2.0)
    with pytest.warns(ConvergenceWarning, match=r"^KMeans: no convergence in 1 iterations \(tol 0.0001\)$"):
        assert not KMeans(5, max_iter=1, random_state=1).fit(X).converged_
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        assert KMeans(5, random_state=1).fit(X).n_iter_ > 1  # the same data need more than one iteration


def test_constructor_is_keyword_only_after_n_clusters():
    assert KMeans(3).n_clusters == 3
    with pytest.raises(TypeError):
        KMeans(3, 50)
