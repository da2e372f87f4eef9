"""A trained regressor (pose PCA, Eq. 1, and MVRVM, Section 3) as arrays: ``regressor.h5`` and the model file.

The files keep the MVRVM's posterior mean and the factorisation of its posterior covariance, so a regressor read
back predicts poses and their standard deviations (``MVRVM.predict(return_std=True)``) as the fitted one did.
Files written before the covariance was kept still load and predict means.
"""

from voxpose.regression.mvrvm import MVRVM
from voxpose.regression.pose_space import PosePCA


def regressor_arrays(pca: PosePCA, mvrvm: MVRVM) -> tuple[dict, dict]:
    """The pose PCA and fitted MVRVM as (arrays, meta), for ``regressor.h5`` and the model file."""
    pca_arrays, _ = pca.to_arrays()
    arrays, meta = mvrvm.to_arrays()
    return {f"pca_{k}": v for k, v in pca_arrays.items()} | arrays, meta


def regressor_from_arrays(arrays: dict, meta: dict) -> tuple[PosePCA, MVRVM]:
    """Inverse of ``regressor_arrays``: a PCA and an MVRVM that transform and predict."""
    pca = PosePCA.from_arrays({k.removeprefix("pca_"): v for k, v in arrays.items() if k.startswith("pca_")}, {})
    return pca, MVRVM.from_arrays({k: v for k, v in arrays.items() if not k.startswith("pca_")}, meta)
