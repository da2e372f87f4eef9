"""A trained regressor (pose PCA, Eq. 1, and MVRVM, Section 3) as arrays: ``regressor.h5`` and the model file."""

from voxpose.regression.mvrvm import MVRVM
from voxpose.regression.pose_space import PosePCA


def regressor_arrays(pca: PosePCA, mvrvm: MVRVM) -> tuple[dict, dict]:
    """The pose PCA and fitted MVRVM as (arrays, meta), for ``regressor.h5`` and the model file."""
    arrays = {"pca_mean": pca.mean_, "pca_components": pca.components_, "relevance": mvrvm.relevance_,
              "relevance_vectors": mvrvm.relevance_vectors_, "coef": mvrvm.coef_, "alpha": mvrvm.alpha_,
              "beta": mvrvm.beta_}  # fmt: skip
    meta = {"kernel_width": mvrvm.kernel_width_, "has_bias": bool(mvrvm.has_bias_),
            "log_marginal_likelihood": list(map(float, mvrvm.log_marginal_likelihood_))}  # fmt: skip
    return arrays, meta


def regressor_from_arrays(arrays: dict, meta: dict) -> tuple[PosePCA, MVRVM]:
    """Inverse of ``regressor_arrays``: a PCA and an MVRVM that transform and predict (no ``return_std``)."""
    pca = PosePCA()
    pca.mean_, pca.components_ = arrays["pca_mean"], arrays["pca_components"]
    pca.n_components_ = len(pca.components_)
    mvrvm = MVRVM(kernel_width=float(meta["kernel_width"]))
    mvrvm.relevance_, mvrvm.relevance_vectors_ = arrays["relevance"], arrays["relevance_vectors"]
    mvrvm.coef_, mvrvm.alpha_, mvrvm.beta_ = arrays["coef"], arrays["alpha"], arrays["beta"]
    mvrvm.kernel_width_, mvrvm.has_bias_ = float(meta["kernel_width"]), bool(meta["has_bias"])
    mvrvm.log_marginal_likelihood_ = list(meta.get("log_marginal_likelihood", []))
    mvrvm._single_output = False
    return pca, mvrvm
