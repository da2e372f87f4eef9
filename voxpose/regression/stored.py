"""A trained regressor (pose PCA, Eq. 1, and MVRVM, Section 3) as arrays: ``regressor.h5`` and the model file.

The files keep the MVRVM's posterior mean, not its covariance: a regressor read back predicts poses but not
their standard deviations (``MVRVM.predict(return_std=True)``).
"""

from voxpose.regression.mvrvm import MVRVM
from voxpose.regression.pose_space import PosePCA

_MVRVM_ARRAYS = ("relevance", "relevance_vectors", "coef", "alpha", "beta")
"""The MVRVM arrays the files keep (the PCA's are ``pca_mean`` and ``pca_components``)."""


def regressor_arrays(pca: PosePCA, mvrvm: MVRVM) -> tuple[dict, dict]:
    """The pose PCA and fitted MVRVM as (arrays, meta), for ``regressor.h5`` and the model file."""
    pca_arrays, _ = pca.to_arrays()
    arrays, meta = mvrvm.to_arrays()
    return {f"pca_{k}": v for k, v in pca_arrays.items()} | {k: arrays[k] for k in _MVRVM_ARRAYS}, meta


def regressor_from_arrays(arrays: dict, meta: dict) -> tuple[PosePCA, MVRVM]:
    """Inverse of ``regressor_arrays``: a PCA and an MVRVM that transform and predict (no ``return_std``)."""
    pca = PosePCA.from_arrays({k.removeprefix("pca_"): v for k, v in arrays.items() if k.startswith("pca_")}, {})
    return pca, MVRVM.from_arrays(arrays, meta)
