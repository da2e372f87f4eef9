"""The design statistics of the MVRVM (Eq. 3) built block by block against the dense design matrix."""

import numpy as np
import pytest

from voxpose.regression import design_statistics
from voxpose.regression.design_statistics import DesignStatistics
from voxpose.regression.kernels import design_matrix, gaussian_kernel


@pytest.mark.parametrize("bias", [True, False])
@pytest.mark.parametrize("block_elements", [1, 7 * 31, 1 << 22])  # one row per block, a ragged last block, one block
def test_block_built_statistics_equal_the_dense_ones(monkeypatch, bias, block_elements):
    monkeypatch.setattr(design_statistics, "_BLOCK_ELEMENTS", block_elements)
    rng = np.random.default_rng(0)
    x, centres, y = rng.standard_normal((50, 3)), rng.standard_normal((30, 3)), rng.standard_normal((50, 4))
    phi = design_matrix(x, centres, 1.3, bias)
    stats = DesignStatistics(x, centres, 1.3, bias, y)
    assert stats.n == 50 and stats.n_basis == phi.shape[1]
    np.testing.assert_allclose(stats.gram, phi.T @ phi, rtol=0, atol=1e-10)
    np.testing.assert_array_equal(stats.gram, stats.gram.T)
    np.testing.assert_allclose(stats.phity, phi.T @ y, rtol=0, atol=1e-10)
    np.testing.assert_allclose(stats.yy, np.sum(y * y, axis=0), rtol=1e-14)
    for j in range(phi.shape[1]):
        np.testing.assert_allclose(stats.column(j), phi[:, j], rtol=0, atol=1e-15)


def test_columns_are_the_kernel_bit_for_bit_and_the_gaussians_of_the_distances():
    """``column`` reuses the rows' squared norms: the same numbers as ``gaussian_kernel`` computing them itself,
    and the Gaussian of the brute-force distances; on rows far from the origin (large norms, small distances)."""
    rng = np.random.default_rng(1)
    x = 30.0 + rng.standard_normal((40, 5))
    stats = DesignStatistics(x, x[::3], 0.9, True, rng.standard_normal((40, 2)))
    for j in range(1, stats.n_basis):
        centre = x[::3][j - 1]
        np.testing.assert_array_equal(stats.column(j), gaussian_kernel(x, centre[None], 0.9)[:, 0])
        brute = np.exp(-np.array([np.sum((row - centre) ** 2) for row in x]) / (2 * 0.9**2))
        np.testing.assert_allclose(stats.column(j), brute, rtol=1e-9, atol=1e-12)
