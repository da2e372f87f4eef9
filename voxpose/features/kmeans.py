"""Seeded k-means++ and Lloyd k-means, streamed over row chunks.

One implementation serves two uses: the initialisation of the MPPCA model (:mod:`voxpose.features.mppca`) and the
K-means feature baseline of Sun et al. (2006), Table 1 third row, which follows
Agarwal & Triggs (2004) in clustering all training descriptors. Memory stays O(n_clusters * d) plus one chunk
of rows and O(n_samples) labels, so half a million 200-d descriptors cluster in well under a GiB beyond ``X``.

The helpers :func:`group_sums`, :func:`nearest_centres` and :func:`mean_feature_variance` are shared with
:mod:`voxpose.features.mppca` and :mod:`voxpose.features.frame`.
"""

import logging
import warnings

import numpy as np
import scipy.sparse

from voxpose.errors import ConvergenceWarning, VoxposeError
from voxpose.features.kmeans_bounds import BoundedAssignment
from voxpose.validation import as_rows, check_fitted, integer, squared_distances

log = logging.getLogger(__name__)

DEFAULT_CHUNK_SIZE = 4096


def group_sums(index, values, n_groups):
    """Sum the rows of ``values`` (n, m) by group ``index`` (n,) into shape (n_groups, m).

    A sparse one-hot product, much faster than ``np.add.at`` for many rows.
    """
    n = index.shape[0]
    onehot = scipy.sparse.csr_matrix((np.ones(n), (index, np.arange(n))), shape=(n_groups, n))
    return np.asarray(onehot @ values)


def nearest_centres(X, centres, chunk_size=DEFAULT_CHUNK_SIZE):
    """Index of and squared distance to the nearest centre for every row of ``X``: (n,) int, (n,) float64."""
    labels = np.empty(X.shape[0], dtype=np.intp)
    sqdist = np.empty(X.shape[0])
    for start in range(0, X.shape[0], chunk_size):
        d2 = squared_distances(X[start : start + chunk_size], centres)
        labels[start : start + len(d2)] = np.argmin(d2, axis=1)
        sqdist[start : start + len(d2)] = d2[np.arange(len(d2)), labels[start : start + len(d2)]]
    return labels, sqdist


def _float_chunks(X, chunk_size):
    """Yield consecutive blocks of at most ``chunk_size`` rows of ``X`` as float64 arrays."""
    for start in range(0, X.shape[0], chunk_size):
        yield np.asarray(X[start : start + chunk_size], dtype=np.float64)


def mean_feature_variance(X, chunk_size=DEFAULT_CHUNK_SIZE):
    """Average over features of the per-feature variance of ``X`` (two chunked passes, float64)."""
    mean = sum(block.sum(axis=0) for block in _float_chunks(X, chunk_size)) / X.shape[0]
    return sum(float(((block - mean) ** 2).sum()) for block in _float_chunks(X, chunk_size)) / X.size


def kmeans_plus_plus(X, n_clusters, rng, chunk_size=DEFAULT_CHUNK_SIZE):
    """Seed centres by k-means++ (Arthur & Vassilvitskii 2007): each next centre is drawn with probability
    proportional to the squared distance to the nearest centre chosen so far.

    Returns
    -------
    centres : ndarray, shape (n_clusters, d), float64 copies of rows of ``X``.

    Raises
    ------
    VoxposeError
        If ``X`` has fewer distinct rows than ``n_clusters``.
    """
    n = X.shape[0]
    row_sq = np.concatenate([np.einsum("nd,nd->n", block, block) for block in _float_chunks(X, chunk_size)])
    closest = np.full(n, np.inf)
    chosen = [int(rng.integers(n))]
    for _ in range(1, n_clusters):
        centre = np.asarray(X[chosen[-1]], dtype=np.float64)
        for start, rows in zip(range(0, n, chunk_size), _float_chunks(X, chunk_size), strict=True):
            d2 = row_sq[start : start + len(rows)] - 2.0 * (rows @ centre) + centre @ centre
            np.minimum(closest[start : start + len(rows)], d2, out=closest[start : start + len(rows)])
        cumulative = np.cumsum(np.maximum(closest, 0.0))
        if cumulative[-1] <= 0.0:
            raise VoxposeError(
                f"the data have fewer distinct rows than the {n_clusters} clusters (or components) requested"
            )
        pick = int(np.searchsorted(cumulative, rng.random() * cumulative[-1], side="right"))
        chosen.append(min(pick, n - 1))
    return np.asarray(X[chosen], dtype=np.float64)


class KMeans:
    """K-means clustering: k-means++ seeding, then Lloyd iterations streamed over row chunks.

    Each iteration's assignment skips the rows whose nearest centre Hamerly's bounds prove unchanged
    (:mod:`voxpose.features.kmeans_bounds`): the same labels and centres as plain Lloyd iterations, with most
    distances left uncomputed once the centres settle.

    Parameters
    ----------
    n_clusters : int
        Number of centres K.
    max_iter : int
        Maximum number of Lloyd iterations.
    tol : float
        Convergence threshold on the summed squared centre shift of one iteration, relative to the mean
        per-feature variance of the data (scikit-learn's convention). Iterations also stop when no label
        changes.
    chunk_size : int
        Rows processed at once; bounds the working memory to about ``chunk_size * K`` floats.
    random_state : int, numpy Generator or None
        Seed of the k-means++ draws.

    Attributes
    ----------
    cluster_centers_ : ndarray, shape (K, d)
    labels_ : ndarray, shape (n_samples,)
        Nearest centre of each training row under the final ``cluster_centers_``.
    inertia_ : float
        Sum of squared distances of the training rows to their nearest final centre.
    n_iter_ : int
    converged_ : bool

    Notes
    -----
    A cluster that empties during the Lloyd iterations is moved onto the training row farthest from its centre
    (the farthest rows first, one per empty cluster); that row's old cluster is corrected on the next pass.
    """

    def __init__(self, n_clusters=100, *, max_iter=100, tol=1e-4, chunk_size=DEFAULT_CHUNK_SIZE, random_state=None):
        self.n_clusters = n_clusters
        self.max_iter = max_iter
        self.tol = tol
        self.chunk_size = chunk_size
        self.random_state = random_state

    def _check_params(self, n_samples):
        """Validate the hyper-parameters against the number of rows; return the chunk size."""
        if integer(self.n_clusters, "n_clusters") > n_samples:
            raise VoxposeError(f"n_clusters={self.n_clusters} needs between 1 and n_samples={n_samples} clusters")
        integer(self.max_iter, "max_iter")
        if not np.isfinite(self.tol) or self.tol < 0:
            raise VoxposeError(f"tol must be a non-negative number, got {self.tol!r}")
        return integer(self.chunk_size, "chunk_size")

    def fit(self, X):
        """Cluster the rows of ``X`` (n_samples, d); returns ``self``."""
        X = as_rows(X, "k-means input", dtype=None)
        chunk = self._check_params(X.shape[0])
        rng = np.random.default_rng(self.random_state)
        threshold = self.tol * mean_feature_variance(X, chunk)
        centres = kmeans_plus_plus(X, self.n_clusters, rng, chunk)
        labels = None
        self.converged_ = False
        assignment = BoundedAssignment(X, chunk)
        for n_iter in range(1, self.max_iter + 1):
            self.n_iter_ = n_iter
            new_labels = assignment.assign(centres)
            sums = np.zeros_like(centres)
            for start in range(0, X.shape[0], chunk):
                sums += group_sums(new_labels[start : start + chunk], X[start : start + chunk], self.n_clusters)
            counts = np.bincount(new_labels, minlength=self.n_clusters)
            new_centres = sums / np.maximum(counts, 1)[:, None]
            empty = np.flatnonzero(counts == 0)
            if empty.size:  # the farthest rows by Lloyd's own distances, which the bounds do not keep
                farthest = np.argsort(nearest_centres(X, centres, chunk)[1])[::-1][: empty.size]
                new_centres[empty] = X[farthest]
                log.info("k-means iteration %d: moved %d empty clusters", self.n_iter_, empty.size)
            shift = float(((new_centres - centres) ** 2).sum())
            unchanged = labels is not None and np.array_equal(labels, new_labels) and not empty.size
            centres, labels = new_centres, new_labels
            log.debug("k-means iteration %d: %d of %d rows' distances computed, centre shift %.3g", self.n_iter_,
                      assignment.recomputed, X.shape[0], shift)  # fmt: skip
            if unchanged or shift <= threshold:
                self.converged_ = True
                break
        self.cluster_centers_ = centres
        self.labels_, sqdist = nearest_centres(X, centres, chunk)
        self.inertia_ = float(sqdist.sum())
        if not self.converged_:
            warnings.warn(
                f"KMeans: no convergence in {self.n_iter_} iterations (tol {self.tol:g})", ConvergenceWarning, 2
            )
        log.info(
            "k-means: %d clusters, %d iterations (converged: %s), inertia %.6g",
            self.n_clusters,
            self.n_iter_,
            self.converged_,
            self.inertia_,
        )
        return self

    def to_arrays(self) -> tuple[dict, dict]:
        """The fitted centres and fit record as (arrays, meta); ``from_arrays`` inverts it (``labels_``, one per
        training row, is not kept)."""
        check_fitted(self, "cluster_centers_")
        return {"centres": self.cluster_centers_}, {"inertia": self.inertia_, "n_iter": self.n_iter_,
                                                    "converged": self.converged_}  # fmt: skip

    @classmethod
    def from_arrays(cls, arrays: dict, meta: dict) -> "KMeans":
        """The KMeans that ``to_arrays`` recorded, fitted: it predicts as the original did."""
        model = cls(len(arrays["centres"]))
        model.cluster_centers_ = arrays["centres"]
        model.inertia_, model.n_iter_, model.converged_ = meta["inertia"], meta["n_iter"], meta["converged"]
        return model

    def predict(self, X):
        """Nearest-centre index of each row of ``X`` (n, d): shape (n,)."""
        check_fitted(self, "cluster_centers_")
        X = as_rows(X, "k-means input", self.cluster_centers_.shape[1], dtype=None)
        return nearest_centres(X, self.cluster_centers_, integer(self.chunk_size, "chunk_size"))[0]
