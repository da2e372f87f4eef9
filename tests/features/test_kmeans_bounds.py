"""Hamerly's bounds in Lloyd's assignment: the labels of a brute-force argmin at every step, rows skipped once
the centres settle, and whole k-means fits equal to plain Lloyd iterations bit for bit."""

import numpy as np
import pytest

import voxpose.features.kmeans as kmeans_module
from voxpose.features.kmeans import KMeans, group_sums, kmeans_plus_plus, nearest_centres
from voxpose.features.kmeans_bounds import BoundedAssignment


def brute_force_labels(X, centres):
    return np.array([int(np.argmin([((x - c) ** 2).sum() for c in centres])) for x in X])


def plain_lloyd(X, n_clusters, seed, chunk, max_iter=100, tol=1e-4):
    """The reference: k-means++ as KMeans seeds it, then Lloyd iterations computing every distance."""
    rng = np.random.default_rng(seed)
    threshold = tol * kmeans_module.mean_feature_variance(X, chunk)
    centres, labels, n_iter = kmeans_plus_plus(X, n_clusters, rng, chunk), None, 0
    while n_iter < max_iter:
        n_iter += 1
        new_labels, sqdist = nearest_centres(X, centres, chunk)
        sums = sum(group_sums(new_labels[s : s + chunk], X[s : s + chunk], n_clusters) for s in range(0, len(X), chunk))
        counts = np.bincount(new_labels, minlength=n_clusters)
        new_centres = sums / np.maximum(counts, 1)[:, None]
        empty = np.flatnonzero(counts == 0)
        new_centres[empty] = X[np.argsort(sqdist)[::-1][: empty.size]]
        shift = float(((new_centres - centres) ** 2).sum())
        unchanged = labels is not None and np.array_equal(labels, new_labels) and not empty.size
        centres, labels = new_centres, new_labels
        if unchanged or shift <= threshold:
            break
    return centres, nearest_centres(X, centres, chunk)[0], n_iter


def test_labels_are_the_brute_force_argmin_while_centres_wander_and_jump():
    rng = np.random.default_rng(3)
    X = rng.normal(size=(300, 4)) + 6.0 * rng.integers(0, 3, size=(300, 1))
    centres = X[rng.choice(300, 7, replace=False)].copy()
    assignment = BoundedAssignment(X, chunk_size=64)
    skipped = 0
    for step in range(40):
        np.testing.assert_array_equal(assignment.assign(centres), brute_force_labels(X, centres))
        skipped += 300 - assignment.recomputed
        centres = centres + rng.normal(scale=0.5 * 0.8**step, size=centres.shape)
        if step == 20:
            centres[2] = 100.0  # a centre thrown far away (as an emptied cluster is moved) and back
        if step == 21:
            centres[2] = X[0]
    assert skipped > 300 * 20  # once the steps are small most rows keep their label without a distance


def test_one_centre_and_exact_ties_keep_lloyds_labels():
    X = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.5, 3.0]])
    one = BoundedAssignment(X, chunk_size=2)
    for shift in (0.0, 0.1, 0.3):
        np.testing.assert_array_equal(one.assign(np.array([[shift, 0.0]])), np.zeros(4, dtype=int))
    ties = BoundedAssignment(X, chunk_size=2)  # row 1 is equidistant from both centres at every step
    for shift in (0.0, 0.25, 0.5):
        centres = np.array([[1.0 - shift - 1.0, 0.0], [1.0 + shift + 1.0, 0.0]])
        labels = ties.assign(centres)
        np.testing.assert_array_equal(labels, nearest_centres(X, centres)[0])
        assert labels[1] == 0  # argmin's first index, as Lloyd breaks the tie


@pytest.mark.parametrize(("n", "d", "k", "chunk", "seed"), [(2000, 20, 30, 256, 0), (1500, 200, 50, 4096, 1)])
def test_fit_equals_plain_lloyd_bit_for_bit(n, d, k, chunk, seed):
    rng = np.random.default_rng(seed)
    # sparse non-negative histogram-like rows in overlapping groups, as shape contexts are
    base = rng.random((12, d)) ** 6
    X = (base[rng.integers(0, 12, n)] + 0.3 * rng.random((n, d)) ** 8).astype(np.float32)
    model = KMeans(k, chunk_size=chunk, random_state=seed).fit(X)
    centres, labels, n_iter = plain_lloyd(X, k, seed, chunk)
    assert model.n_iter_ == n_iter > 5
    np.testing.assert_array_equal(model.cluster_centers_, centres)
    np.testing.assert_array_equal(model.labels_, labels)
