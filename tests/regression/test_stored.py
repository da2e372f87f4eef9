"""A trained regressor as arrays: the stored layout of regressor.h5 and the model file, and a read-back regressor
that predicts exactly as the trained one."""

import numpy as np
import pytest

from tests.helpers import mvrvm_toy
from voxpose.errors import VoxposeError
from voxpose.io.hdf5 import read_arrays, write_arrays
from voxpose.regression.mvrvm import MVRVM
from voxpose.regression.pose_space import PosePCA
from voxpose.regression.stored import regressor_arrays, regressor_from_arrays


def test_regressor_file_layout_and_read_back(tmp_path):
    x, y, _ = mvrvm_toy(n=80, seed=2)
    angles = np.hstack([y, y @ np.array([[1.0, 0.5], [0.0, 1.0], [2.0, -1.0]])])  # 5 angles of rank 3
    pca = PosePCA(0.99).fit(angles)
    mvrvm = MVRVM(kernel_width=1.5).fit(x, pca.transform(angles))
    arrays, meta = regressor_arrays(pca, mvrvm)
    # the names every regressor.h5 and model file has held: readers elsewhere rely on them
    assert list(arrays) == ["pca_mean", "pca_components", "relevance", "relevance_vectors", "coef", "alpha", "beta",
                            "cov_factor", "cov_scale"]  # fmt: skip
    assert list(meta) == ["kernel_width", "has_bias", "log_marginal_likelihood"]
    write_arrays(tmp_path / "regressor.h5", "regressor", arrays, meta)
    pca_back, mvrvm_back = regressor_from_arrays(*read_arrays(tmp_path / "regressor.h5", "regressor"))
    expected = pca.inverse_transform(mvrvm.predict(x))
    np.testing.assert_array_equal(pca_back.inverse_transform(mvrvm_back.predict(x)), expected)
    # a regressor read back gives the predictive standard deviations of the fitted one
    mean, std = mvrvm.predict(x, return_std=True)
    mean_back, std_back = mvrvm_back.predict(x, return_std=True)
    np.testing.assert_array_equal(mean_back, mean)
    np.testing.assert_allclose(std_back, std, rtol=1e-12)
    # a file written before the covariance was kept: means, and a clear error for the deviations
    old = {k: v for k, v in arrays.items() if not k.startswith("cov_")}
    _, means_only = regressor_from_arrays(old, meta)
    np.testing.assert_array_equal(means_only.predict(x), mvrvm.predict(x))
    with pytest.raises(VoxposeError, match="without its posterior covariance"):
        means_only.predict(x, return_std=True)
    # the likelihood trace is a record of the fit, not needed to predict: files without it still read
    _, without_trace = regressor_from_arrays(arrays, {k: meta[k] for k in ("kernel_width", "has_bias")})
    np.testing.assert_array_equal(without_trace.predict(x), mvrvm.predict(x))
