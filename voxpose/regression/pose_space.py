"""The low-dimensional pose space of Section 2: PCA of the 42 joint angles, M chosen by Eq. 1.

Eq. 1 keeps the smallest ``M`` whose leading eigenvalues explain strictly more than the threshold (90 %)
of the total variance of the training angle vectors y'. The regressor (Section 3) then predicts the M
coordinates ``y``, and ``inverse_transform`` maps them back to y'.

Choices where the paper is silent or loose:

* Eq. 1 prints ``1 < M < m'``; we allow ``1 <= M < m'``, since a single component may well explain the
  threshold on a simple training set, and cap ``M`` at ``m' - 1`` (a threshold so high that it needs every
  component is an error of the caller).
* "Strictly more" is tested with a relative tolerance of 1e-9: a cumulative ratio within 1e-9 of the
  threshold counts as *equal* to it, so planted spectra exactly at the threshold behave as written.
* The angles are used as given (unwrapped over time, degrees), centred by the training mean, unscaled:
  all 42 share one unit, and Eq. 1 speaks of the covariance matrix, not the correlation matrix.
"""

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.validation import as_rows, check_fitted

_TIE = 1e-9


def n_components_for(eigenvalues, variance: float) -> int:
    """Eq. 1: the smallest M with ``sum(lambda[:M]) / sum(lambda) > variance`` (eigenvalues decreasing)."""
    lam = np.asarray(eigenvalues, dtype=np.float64)
    total = lam.sum()
    if total <= 0.0:
        raise VoxposeError("pose PCA: the training poses have no variance (all angle vectors are equal)")
    above = np.flatnonzero(np.cumsum(lam) / total > variance * (1.0 + _TIE))
    return int(above[0] + 1) if above.size else lam.size


class PosePCA:
    """PCA of y' (N, m') with M set by Eq. 1.

    Parameters
    ----------
    variance : threshold in (0, 1) on the explained variance ratio; Eq. 1 uses 0.90.

    Attributes
    ----------
    mean_ : (m',) mean training angle vector (degrees).
    components_ : (M, m') orthonormal principal directions, largest eigenvalue first.
    eigenvalues_ : (min(N - 1, m'),) all covariance eigenvalues lambda_i of Eq. 1, decreasing.
    explained_variance_ratio_ : (M,) lambda_i / sum(lambda) of the kept components.
    n_components_ : M.
    """

    def __init__(self, variance: float = 0.90):
        self.variance = variance

    def fit(self, angles) -> "PosePCA":
        """Fit on training angle vectors ``angles`` (N, m') in degrees; returns ``self``."""
        if not 0.0 < float(self.variance) < 1.0:
            raise VoxposeError(f"pose PCA: variance threshold must lie in (0, 1), got {self.variance!r}")
        x = as_rows(angles, "pose PCA: angles")
        n, m = x.shape
        if n < 2 or m < 2:
            raise VoxposeError(f"pose PCA: needs at least 2 poses of at least 2 angles, got shape {x.shape}")
        self.mean_ = x.mean(axis=0)
        # SVD of the centred data: eigenvalues s^2 / (N - 1) without forming the covariance matrix
        _, s, vt = np.linalg.svd(x - self.mean_, full_matrices=False)
        self.eigenvalues_ = s[: min(n - 1, m)] ** 2 / (n - 1)
        m_keep = n_components_for(self.eigenvalues_, float(self.variance))
        if m_keep >= m:
            raise VoxposeError(
                f"pose PCA: variance threshold {self.variance} needs all {m} components (Eq. 1 requires M < m')"
            )
        self.n_components_ = m_keep
        self.components_ = vt[:m_keep]
        self.explained_variance_ratio_ = self.eigenvalues_[:m_keep] / self.eigenvalues_.sum()
        return self

    def to_arrays(self) -> tuple[dict, dict]:
        """What ``transform`` and ``inverse_transform`` need, as (arrays, meta); ``from_arrays`` inverts it.

        The spectrum (``eigenvalues_``, ``explained_variance_ratio_``) describes the fit and is not kept.
        """
        check_fitted(self, "components_")
        return {"mean": self.mean_, "components": self.components_}, {}

    @classmethod
    def from_arrays(cls, arrays: dict, meta: dict) -> "PosePCA":
        """The PosePCA that ``to_arrays`` recorded, fitted: it transforms as the original did."""
        pca = cls()
        pca.mean_, pca.components_ = arrays["mean"], arrays["components"]
        pca.n_components_ = len(pca.components_)
        return pca

    def transform(self, angles) -> np.ndarray:
        """Angle vectors (n, m') -> pose-space coordinates y (n, M)."""
        check_fitted(self, "components_")
        x = as_rows(angles, "pose PCA: angles", self.mean_.size)
        return (x - self.mean_) @ self.components_.T

    def inverse_transform(self, coords) -> np.ndarray:
        """Pose-space coordinates y (n, M) -> angle vectors y' (n, m') in degrees."""
        check_fitted(self, "components_")
        y = as_rows(coords, "pose PCA: coordinates", self.n_components_)
        return y @ self.components_ + self.mean_
