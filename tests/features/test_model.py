"""The stored feature model: the layout of features.h5 and the model file's feature group, and a read-back
model whose features equal the fitted one's."""

import numpy as np
import pytest

from voxpose.features.model import FeatureModel
from voxpose.io.hdf5 import read_arrays

CFG = {"n_components": 4, "n_latent": 2, "max_iter": 50, "tol": 1e-4, "fit_subsample": 500, "kmeans_neighbours": 2}
BASE = ["method", "params", "seed", "n_fit", "n_train"]


@pytest.mark.parametrize(
    "method, array_names, meta_keys",
    [
        ("mppca", ["components", "means", "noise_variance", "weights"],
         [*BASE, "log_likelihood", "n_iter", "converged", "n_reseeded", "noise_variance_floor"]),
        ("kmeans", ["centres"], [*BASE, "inertia", "n_iter", "converged", "n_nearest", "bandwidth"]),
    ],
)  # fmt: skip
def test_feature_model_file_layout_and_read_back(tmp_path, method, array_names, meta_keys):
    rng = np.random.default_rng(0)
    descriptors = np.abs(rng.normal(size=(800, 6))) + np.repeat(np.eye(6)[:4] * 3, 200, axis=0)
    model = FeatureModel.fit(method, descriptors, CFG, seed=1)
    model.save(tmp_path / "features.h5")
    arrays, meta = read_arrays(tmp_path / "features.h5", "feature-model")
    assert sorted(arrays) == array_names and list(meta) == meta_keys
    assert meta["n_fit"] == 500 and meta["n_train"] == 800
    frames = np.repeat(np.arange(8), 100)
    fitted, counts = model.transform(descriptors, frames, 8)  # a fitted MPPCA scores on the compiled path
    loaded, loaded_counts = FeatureModel.load(tmp_path / "features.h5").compiled().transform(descriptors, frames, 8)
    np.testing.assert_array_equal(loaded, fitted)
    np.testing.assert_array_equal(loaded_counts, counts)
    np.testing.assert_allclose(fitted.sum(axis=1), 1.0)
    numpy_path, numpy_counts = FeatureModel.load(tmp_path / "features.h5").transform(descriptors, frames, 8)
    np.testing.assert_allclose(numpy_path, fitted, rtol=1e-12, atol=1e-30)  # the screened path: rounding and 1e-30
    np.testing.assert_array_equal(numpy_counts, counts)
    assert getattr(FeatureModel.load(tmp_path / "features.h5").compiled().estimator, "compiled", None) is (
        True if method == "mppca" else None
    )
