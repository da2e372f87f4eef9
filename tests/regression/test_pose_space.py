"""Pose PCA (Section 2, Eq. 1) against planted spectra and exact reconstructions."""

import numpy as np
import pytest

from voxpose.errors import NotFittedError, VoxposeError
from voxpose.regression.pose_space import PosePCA, n_components_for


def planted(eigenvalues, n=200, seed=0):
    """Data (n, m) whose sample covariance has exactly ``eigenvalues`` along random orthonormal axes."""
    rng = np.random.default_rng(seed)
    m = len(eigenvalues)
    scores = rng.standard_normal((n, m))
    scores -= scores.mean(axis=0)
    q, _ = np.linalg.qr(scores)  # orthonormal, zero-mean columns
    axes, _ = np.linalg.qr(rng.standard_normal((m, m)))
    data = (q * np.sqrt(np.asarray(eigenvalues) * (n - 1))) @ axes.T
    return data + rng.uniform(-50, 50, size=m), axes


@pytest.mark.parametrize(
    "eigenvalues, variance, expected",
    [
        ([5, 4, 0.5, 0.5], 0.90, 3),  # cumulative 0.5, 0.9, 0.95: exactly 90 % is not "more than"
        ([5, 4, 0.5, 0.5], 0.89, 2),
        ([5, 4, 0.5, 0.5], 0.50, 2),  # exactly 50 % after one component
        ([5, 4, 0.5, 0.5], 0.49, 1),
        ([9.5, 0.2, 0.2, 0.1], 0.90, 1),  # M = 1 allowed
    ],
)
def test_eq1_keeps_smallest_m_strictly_above_threshold(eigenvalues, variance, expected):
    assert n_components_for(eigenvalues, variance) == expected
    data, _ = planted(eigenvalues)
    pca = PosePCA(variance).fit(data)
    assert pca.n_components_ == expected
    assert np.allclose(pca.eigenvalues_, eigenvalues)
    assert np.allclose(pca.explained_variance_ratio_, np.asarray(eigenvalues[:expected]) / np.sum(eigenvalues))


def test_components_span_the_planted_axes_and_reconstruct():
    lam = [10.0, 6.0, 3.0, 0.0, 0.0, 0.0]  # rank 3: three components reconstruct exactly
    data, axes = planted(lam, seed=3)
    pca = PosePCA(0.95).fit(data)
    assert pca.n_components_ == 3
    # each component is +- one planted axis
    assert np.allclose(np.abs(pca.components_ @ axes[:, :3]), np.eye(3), atol=1e-8)
    coords = pca.transform(data)
    assert coords.shape == (len(data), 3)
    assert np.allclose(pca.inverse_transform(coords), data, atol=1e-8)
    assert np.allclose(pca.mean_, data.mean(axis=0))


def test_threshold_needing_every_component_is_rejected():
    data, _ = planted([1.0, 1.0, 1.0])
    with pytest.raises(VoxposeError, match="needs all 3"):
        PosePCA(0.9).fit(data)


@pytest.mark.parametrize(
    "data, variance, message",
    [
        (np.zeros((5, 4)), 0.9, "no variance"),
        (np.ones((1, 42)), 0.9, "at least 2 poses"),
        (np.full((3, 4), np.nan), 0.9, "NaN"),
        (np.eye(4), 1.0, r"\(0, 1\)"),
        (np.eye(4), 0.0, r"\(0, 1\)"),
    ],
)
def test_bad_input_raises(data, variance, message):
    with pytest.raises(VoxposeError, match=message):
        PosePCA(variance).fit(data)


def test_transform_checks_fit_and_width():
    unfitted = PosePCA()
    for use in (unfitted.transform, unfitted.inverse_transform):
        with pytest.raises(NotFittedError, match=r"^PosePCA is not fitted: call fit first$"):
            use(np.zeros((2, 42)))
    with pytest.raises(NotFittedError, match="PosePCA is not fitted"):
        unfitted.to_arrays()
    data, _ = planted([5, 4, 0.5, 0.5])
    pca = PosePCA().fit(data)
    with pytest.raises(VoxposeError, match="4 columns"):
        pca.transform(np.zeros((2, 5)))
    with pytest.raises(VoxposeError, match="3 columns"):
        pca.inverse_transform(np.zeros((2, 2)))


def test_restored_pca_transforms_exactly_like_the_fitted_one():
    data, _ = planted([10.0, 6.0, 3.0, 1.0, 0.5])
    pca = PosePCA(0.9).fit(data)
    restored = PosePCA.from_arrays(*pca.to_arrays())
    coords = pca.transform(data)
    np.testing.assert_array_equal(restored.transform(data), coords)
    np.testing.assert_array_equal(restored.inverse_transform(coords), pca.inverse_transform(coords))
    assert restored.n_components_ == pca.n_components_ == 3
