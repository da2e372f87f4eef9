"""Reference regressors to put the MVRVM's errors in context, with the same fit/predict interface.

* ``MeanPose``: always the mean training target (the error of knowing nothing about the input).
* ``NearestNeighbour``: the target of the training row nearest in feature space (Euclidean), the
  exemplar-based approach of Section 1; ties go to the earliest row.
* ``KernelRidge``: kernel ridge regression with the MVRVM's Gaussian kernel (``voxpose.regression.kernels``) on all
  training rows, ``Y - mean(Y) = K a`` regularised by ``ridge * I``; the ridge is chosen on held-out
  training rows when not given. The dense counterpart of the sparse MVRVM.
"""

import logging

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.regression.kernels import gaussian_kernel, median_pairwise_distance, selection_split
from voxpose.validation import as_rows, check_fitted, positive_number, squared_distances

log = logging.getLogger(__name__)

_JITTER_TRIES = 6
_RESTORE_BLOCK = 256  # columns per block of _restore_lower


def _training_pair(X, Y, who: str) -> tuple[np.ndarray, np.ndarray, bool]:
    """Validated (N, d) features and (N, P) targets, and whether Y was 1-D."""
    x = as_rows(X, f"{who}: X")
    y = np.asarray(Y, dtype=np.float64)
    single = y.ndim == 1
    y = as_rows(y[:, None] if single else y, f"{who}: Y")
    if x.shape[0] != y.shape[0]:
        raise VoxposeError(f"{who}: X has {x.shape[0]} rows but Y has {y.shape[0]}")
    return x, y, single


def cholesky_solve(a: np.ndarray, b: np.ndarray, ridge: float = 0.0, overwrite_a: bool = False) -> np.ndarray:
    """Solve ``(a + ridge I) x = b`` for symmetric positive (semi-)definite ``a`` by Cholesky.

    When the factorisation fails (singular to working precision) a jitter of 1e-10 times the mean diagonal is
    added, growing tenfold up to 1e-5, before giving up with a ``VoxposeError``. Memory: one Fortran-ordered copy
    of ``a`` per attempt, its diagonal shifted in place and factored in place (no identity matrices, no second
    copy for LAPACK): on an unthinned real training set (~10^4 rows) each N x N array is 0.8 GB.

    The copy is of ``a.T`` when ``a`` is C-ordered: then it is a straight memory copy, where ordering ``a`` itself
    for Fortran is a transpose (2.4 of the 11.6 s of the factorisation at 10^4 rows, one thread). For the
    symmetric ``a`` this function solves, ``a.T`` is ``a``, and LAPACK gets the same numbers as before.

    ``overwrite_a``: the first attempt factors a C-ordered float64 ``a`` itself (through ``a.T``), without a copy,
    and ``a`` is destroyed: for a caller done with it, 0.8 GB less and no fresh memory to fault in (1.9 s at 10^4
    rows). LAPACK leaves the other triangle alone, so when that attempt fails the factored one is restored from it
    (``a`` is symmetric) before the jittered attempts, which copy as above: the same numbers as without.
    """
    import scipy.linalg  # here, not at the top: jobs that only predict never solve and skip its 0.12 s import

    a = np.asarray(a)
    original = np.diag(a).copy()
    diagonal = original + ridge
    scale = float(np.mean(diagonal))
    in_place = overwrite_a and a.dtype == np.float64 and a.flags.c_contiguous and a.flags.writeable
    jitter = 0.0
    for attempt in range(_JITTER_TRIES + 1):
        first_in_place = in_place and attempt == 0
        work = a.T if first_in_place else np.array(a.T if a.flags.c_contiguous else a, dtype=np.float64, order="F")
        np.fill_diagonal(work, diagonal)
        if jitter:
            work.flat[:: work.shape[0] + 1] += jitter
        try:
            factor = scipy.linalg.cho_factor(work, lower=True, overwrite_a=True, check_finite=False)
        except np.linalg.LinAlgError:
            if first_in_place:
                _restore_lower(work, original)
            jitter = scale * 1e-10 * 10.0**attempt
            continue
        if jitter:
            log.warning("Cholesky: added jitter %.3g to the diagonal", jitter)
        return scipy.linalg.cho_solve(factor, b, check_finite=False)
    raise VoxposeError("kernel ridge: the regularised kernel matrix is not positive definite, even with jitter")


def _restore_lower(work: np.ndarray, diagonal: np.ndarray) -> None:
    """Set the lower triangle of the square ``work`` to its strict upper triangle's mirror, and its diagonal to
    ``diagonal``: a symmetric matrix back from a failed in-place lower Cholesky. Block column by block column."""
    n = work.shape[0]
    for start in range(0, n, _RESTORE_BLOCK):
        stop = min(start + _RESTORE_BLOCK, n)
        work[stop:, start:stop] = work[start:stop, stop:].T
        block = work[start:stop, start:stop]
        lower = np.tril_indices(stop - start, -1)
        block[lower] = block.T[lower]
    np.fill_diagonal(work, diagonal)


class _Baseline:
    """Shared prediction plumbing: 1-D targets in, 1-D predictions out."""

    def _check_input(self, X) -> np.ndarray:
        check_fitted(self, "n_features_in_")
        return as_rows(X, f"{type(self).__name__}: X", self.n_features_in_)

    def _output(self, pred: np.ndarray) -> np.ndarray:
        return pred[:, 0] if self._single_output else pred

    # the fitted state as (arrays, meta), and back: ``_STATE`` names the fitted array attributes,
    # ``_SCALARS`` the fitted scalars, ``_PARAMS`` the constructor's hyper-parameters kept with them
    _STATE: tuple = ()
    _SCALARS: tuple = ()
    _PARAMS: tuple = ()

    def to_arrays(self) -> tuple[dict, dict]:
        """The fitted state as (arrays, meta), for a baselines file."""
        check_fitted(self, "n_features_in_")
        arrays = {name: getattr(self, f"{name}_") for name in self._STATE}
        meta = {name: float(getattr(self, f"{name}_")) for name in self._SCALARS}
        meta |= {name: getattr(self, name) for name in self._PARAMS}
        return arrays, meta | {"n_features_in": int(self.n_features_in_), "single_output": bool(self._single_output)}

    @classmethod
    def from_arrays(cls, arrays: dict, meta: dict):
        """A fitted baseline from ``to_arrays``'s (arrays, meta): it predicts exactly as the one saved."""
        model = cls(**{name: meta[name] for name in cls._PARAMS})
        for name in cls._STATE:
            setattr(model, f"{name}_", np.asarray(arrays[name], dtype=np.float64))
        for name in cls._SCALARS:
            setattr(model, f"{name}_", float(meta[name]))
        model.n_features_in_, model._single_output = int(meta["n_features_in"]), bool(meta["single_output"])
        return model


class MeanPose(_Baseline):
    """Predicts the mean training target for every input. Attribute ``mean_`` (P,)."""

    _STATE = ("mean",)

    def fit(self, X, Y) -> "MeanPose":
        x, y, self._single_output = _training_pair(X, Y, "MeanPose")
        self.n_features_in_ = x.shape[1]
        self.mean_ = y.mean(axis=0)
        return self

    def predict(self, X) -> np.ndarray:
        x = self._check_input(X)
        return self._output(np.tile(self.mean_, (x.shape[0], 1)))


class NearestNeighbour(_Baseline):
    """Predicts the target of the nearest training row (Euclidean distance in feature space).

    Attributes ``X_`` (N, d) and ``Y_`` (N, P): the training rows. Distances are computed in blocks of
    ``block`` query rows to bound memory.
    """

    _STATE = ("X", "Y")
    _PARAMS = ("block",)

    def __init__(self, block: int = 1024):
        self.block = block

    def fit(self, X, Y) -> "NearestNeighbour":
        self.X_, self.Y_, self._single_output = _training_pair(X, Y, "NearestNeighbour")
        self.n_features_in_ = self.X_.shape[1]
        return self

    def neighbours(self, X) -> np.ndarray:
        """Index (n,) of the nearest training row of each query row (the first one on ties)."""
        x = self._check_input(X)
        out = np.empty(x.shape[0], dtype=np.int64)
        for start in range(0, x.shape[0], self.block):
            stop = start + self.block
            out[start:stop] = np.argmin(squared_distances(x[start:stop], self.X_), axis=1)
        return out

    def predict(self, X) -> np.ndarray:
        rows = self.neighbours(X)
        return self._output(self.Y_[rows])


class KernelRidge(_Baseline):
    """Kernel ridge regression with the Gaussian kernel of Eq. 3.

    Parameters
    ----------
    kernel_width : ``w`` of ``exp(-||x - x'||^2 / (2 w^2))``, or ``"median"`` (median pairwise distance).
    ridge : the regulariser ``lambda`` (kernel values are at most 1, so it is relative to the kernel's
        diagonal), or None: chosen from ``ridges`` on held-out training rows (lowest validation RMSE,
        ``voxpose.regression.kernels.holdout_split`` with ``validation_fraction`` and the ``groups`` given to
        ``fit``; groups with a single label hold out rows, as without groups), then refitted on all rows.
    max_rows : the ridge is chosen on at most this many training rows drawn at random
        (``voxpose.regression.kernels.selection_split``, the MVRVM width selection's rule; None: every row), then
        refitted on all: the choice costs six Cholesky factorisations of the fitting rows' kernel, cubic in their
        number, the refit one.
    random_state : seed of the held-out split, of the drawn rows and of the median distance's row subset.

    Attributes
    ----------
    dual_coef_ : (N, P) weights ``a`` of the training rows; ``intercept_`` (P,) the mean target.
    ridge_ : the regulariser used; ``kernel_width_`` the width used; ``validation_`` the ridge table
        (list of ``(ridge, validation RMSE)``) when the ridge was chosen.
    """

    _STATE = ("X", "dual_coef", "intercept")
    _SCALARS = ("kernel_width", "ridge")

    def __init__(
        self,
        kernel_width="median",
        *,
        ridge=None,
        ridges=(1e-4, 1e-3, 1e-2, 1e-1, 1.0, 10.0),
        validation_fraction: float = 0.2,
        max_rows: int | None = None,
        random_state=None,
    ):
        self.kernel_width = kernel_width
        self.ridge = ridge
        self.ridges = ridges
        self.validation_fraction = validation_fraction
        self.max_rows = max_rows
        self.random_state = random_state

    @staticmethod
    def _solve(gram: np.ndarray, y: np.ndarray, ridge: float, overwrite: bool = False) -> tuple[np.ndarray, np.ndarray]:
        mean = y.mean(axis=0)
        return cholesky_solve(gram, y - mean, ridge, overwrite_a=overwrite), mean

    def fit(self, X, Y, groups=None) -> "KernelRidge":
        x, y, self._single_output = _training_pair(X, Y, "KernelRidge")
        if self.kernel_width == "median":
            self.kernel_width_ = median_pairwise_distance(x, random_state=self.random_state)
        else:
            self.kernel_width_ = positive_number(self.kernel_width, "kernel width")
        gram = gaussian_kernel(x, x, self.kernel_width_)
        if self.ridge is None:
            if groups is not None and np.unique(groups).size < 2:  # one motion: nothing whole to hold out
                groups = None
            fit_rows, val_rows = selection_split(x.shape[0], self.max_rows, self.validation_fraction, groups,
                                                 self.random_state, "kernel ridge")  # fmt: skip
            fit_gram, val_gram = gram[np.ix_(fit_rows, fit_rows)], gram[np.ix_(val_rows, fit_rows)]
            table = []
            for ridge in self.ridges:
                coef, mean = self._solve(fit_gram, y[fit_rows], self._check_ridge(ridge))
                err = val_gram @ coef + mean - y[val_rows]
                table.append((float(ridge), float(np.sqrt(np.mean(np.sum(err * err, axis=1))))))
            del fit_gram, val_gram
            self.validation_ = table
            self.ridge_ = min(table, key=lambda row: row[1])[0]
            log.info("kernel ridge: ridge %.3g chosen on %d held-out rows", self.ridge_, val_rows.size)
        else:
            self.ridge_ = self._check_ridge(self.ridge)
        self.dual_coef_, self.intercept_ = self._solve(gram, y, self.ridge_, overwrite=True)  # gram: consumed
        self.X_ = x
        self.n_features_in_ = x.shape[1]
        return self

    @staticmethod
    def _check_ridge(ridge) -> float:
        try:
            value = float(ridge)
        except (TypeError, ValueError):
            raise VoxposeError(f"kernel ridge: ridge must be a non-negative number, got {ridge!r}") from None
        if not (np.isfinite(value) and value >= 0):
            raise VoxposeError(f"kernel ridge: ridge must be a non-negative number, got {ridge!r}")
        return value

    def predict(self, X) -> np.ndarray:
        x = self._check_input(X)
        return self._output(gaussian_kernel(x, self.X_, self.kernel_width_) @ self.dual_coef_ + self.intercept_)
