"""Seeded k-means++ and Lloyd k-means, streamed over row chunks.

One implementation serves two uses: the initialisation of the MPPCA model (:mod:`voxpose.features.mppca`) and the
K-means feature baseline of Sun et al. (2006), Table 1 third row, which follows
Agarwal & Triggs (2004) in clustering all training descriptors. Memory stays O(n_clusters * d) plus one chunk
of rows and O(n_samples) labels, so half a million 200-d descriptors cluster in well under a GiB beyond ``X``.

The helpers :func:`check_rows`, :func:`squared_distances` and :func:`group_sums` are shared with
:mod:`voxpose.features.mppca` and :mod:`voxpose.features.frame`.
"""

import logging

import numpy as np
import scipy.sparse

from voxpose.errors import VoxposeError

log = logging.getLogger(__name__)

DEFAULT_CHUNK_SIZE = 4096


def check_rows(X, name, n_features=None):
    """Validate a 2-D array of finite real rows and return it as an ndarray (no copy when possible).

    Parameters
    ----------
    X : array_like, shape (n_samples, n_features)
    name : str
        What the rows are, for the error message (e.g. ``"descriptors"``).
    n_features : int, optional
        Required number of columns (the fitted model's dimension).

    Raises
    ------
    VoxposeError
        If ``X`` is not 2-D real-valued, has no rows, the wrong number of columns, or a NaN/infinite entry
        (the message names the first bad row).
    """
    X = np.asarray(X)
    if X.ndim != 2:
        raise VoxposeError(f"{name} must be a 2-D array (rows x features), got shape {X.shape}")
    if not (np.issubdtype(X.dtype, np.floating) or np.issubdtype(X.dtype, np.integer)):
        raise VoxposeError(f"{name} must hold real numbers, got dtype {X.dtype}")
    if X.shape[0] == 0:
        raise VoxposeError(f"{name} has no rows")
    if n_features is not None and X.shape[1] != n_features:
        raise VoxposeError(f"{name} has {X.shape[1]} features per row, the model was fitted with {n_features}")
    if np.issubdtype(X.dtype, np.floating):
        for start in range(0, X.shape[0], DEFAULT_CHUNK_SIZE):
            bad = ~np.isfinite(X[start : start + DEFAULT_CHUNK_SIZE]).all(axis=1)
            if bad.any():
                row = start + int(np.argmax(bad))
                raise VoxposeError(f"{name} row {row} contains NaN or infinite values")
    return X


def check_chunk_size(chunk_size):
    """Return ``chunk_size`` as a positive int or raise :class:`VoxposeError`."""
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, int | np.integer) or chunk_size < 1:
        raise VoxposeError(f"chunk_size must be a positive integer, got {chunk_size!r}")
    return int(chunk_size)


def squared_distances(X, centres, centres_sq=None):
    """Squared Euclidean distances between rows and centres, shape (n, K), in float64.

    Uses ``|x|^2 - 2 x.c + |c|^2`` (one matrix product) and clips the round-off negatives at zero.
    """
    X = np.asarray(X, dtype=np.float64)
    if centres_sq is None:
        centres_sq = np.einsum("kd,kd->k", centres, centres)
    d2 = np.einsum("nd,nd->n", X, X)[:, None] - 2.0 * (X @ centres.T) + centres_sq[None, :]
    return np.maximum(d2, 0.0, out=d2)


def group_sums(index, values, n_groups):
    """Sum the rows of ``values`` (n, m) by group ``index`` (n,) into shape (n_groups, m).

    A sparse one-hot product, much faster than ``np.add.at`` for many rows.
    """
    n = index.shape[0]
    onehot = scipy.sparse.csr_matrix((np.ones(n), (index, np.arange(n))), shape=(n_groups, n))
    return np.asarray(onehot @ values)


def nearest_centres(X, centres, chunk_size=DEFAULT_CHUNK_SIZE):
    """Index of and squared distance to the nearest centre for every row of ``X``: (n,) int, (n,) float64."""
    centres_sq = np.einsum("kd,kd->k", centres, centres)
    labels = np.empty(X.shape[0], dtype=np.intp)
    sqdist = np.empty(X.shape[0])
    for start in range(0, X.shape[0], chunk_size):
        d2 = squared_distances(X[start : start + chunk_size], centres, centres_sq)
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
        if isinstance(self.n_clusters, bool) or not isinstance(self.n_clusters, int | np.integer):
            raise VoxposeError(f"n_clusters must be an integer, got {self.n_clusters!r}")
        if not 1 <= self.n_clusters <= n_samples:
            raise VoxposeError(f"n_clusters={self.n_clusters} needs between 1 and n_samples={n_samples} clusters")
        if isinstance(self.max_iter, bool) or not isinstance(self.max_iter, int | np.integer) or self.max_iter < 1:
            raise VoxposeError(f"max_iter must be a positive integer, got {self.max_iter!r}")
        if not np.isfinite(self.tol) or self.tol < 0:
            raise VoxposeError(f"tol must be a non-negative number, got {self.tol!r}")
        return check_chunk_size(self.chunk_size)

    def fit(self, X):
        """Cluster the rows of ``X`` (n_samples, d); returns ``self``."""
        X = check_rows(X, "k-means input")
        chunk = self._check_params(X.shape[0])
        rng = np.random.default_rng(self.random_state)
        threshold = self.tol * mean_feature_variance(X, chunk)
        centres = kmeans_plus_plus(X, self.n_clusters, rng, chunk)
        labels = None
        self.converged_ = False
        for n_iter in range(1, self.max_iter + 1):
            self.n_iter_ = n_iter
            new_labels, sqdist = nearest_centres(X, centres, chunk)
            sums = np.zeros_like(centres)
            for start in range(0, X.shape[0], chunk):
                sums += group_sums(new_labels[start : start + chunk], X[start : start + chunk], self.n_clusters)
            counts = np.bincount(new_labels, minlength=self.n_clusters)
            new_centres = sums / np.maximum(counts, 1)[:, None]
            empty = np.flatnonzero(counts == 0)
            if empty.size:
                farthest = np.argsort(sqdist)[::-1][: empty.size]
                new_centres[empty] = X[farthest]
                log.info("k-means iteration %d: moved %d empty clusters", self.n_iter_, empty.size)
            shift = float(((new_centres - centres) ** 2).sum())
            unchanged = labels is not None and np.array_equal(labels, new_labels) and not empty.size
            centres, labels = new_centres, new_labels
            log.debug("k-means iteration %d: inertia %.6g, centre shift %.3g", self.n_iter_, sqdist.sum(), shift)
            if unchanged or shift <= threshold:
                self.converged_ = True
                break
        self.cluster_centers_ = centres
        self.labels_, sqdist = nearest_centres(X, centres, chunk)
        self.inertia_ = float(sqdist.sum())
        log.info(
            "k-means: %d clusters, %d iterations (converged: %s), inertia %.6g",
            self.n_clusters,
            self.n_iter_,
            self.converged_,
            self.inertia_,
        )
        return self

    def predict(self, X):
        """Nearest-centre index of each row of ``X`` (n, d): shape (n,)."""
        if not hasattr(self, "cluster_centers_"):
            raise VoxposeError("KMeans is not fitted yet: call fit() first")
        X = check_rows(X, "k-means input", self.cluster_centers_.shape[1])
        return nearest_centres(X, self.cluster_centers_, check_chunk_size(self.chunk_size))[0]
