"""Mixture of probabilistic principal component analysers (MPPCA), fitted by EM and streamed over row chunks.

Sun et al. (2006), Sec. 5, model the density of the 3D shape context descriptors with the MPPCA of Tipping &
Bishop (1999), ``p(t) = sum_i pi_i p(t | i)``, where each ``p(t | i) = N(t; mu_i, C_i)`` with
``C_i = sigma_i^2 I + W_i W_i^T`` is a probabilistic PCA model, and describe a frame by the average posterior
``p(i | t_n)`` of its descriptors (Eq. 5, :mod:`voxpose.features.frame`).

Numerics. Densities stay in log space: ``log|C_i| = (d - q) log sigma_i^2 + log|M_i|`` (matrix determinant
lemma) and ``C_i^-1 = (I - W_i M_i^-1 W_i^T) / sigma_i^2`` (Woodbury), with ``M_i = sigma_i^2 I + W_i^T W_i``
(q x q) factored by Cholesky, ``M_i = L_i L_i^T``. With ``V_i = W_i L_i^-T`` the Mahalanobis term is
``(|t - mu_i|^2 - |V_i^T (t - mu_i)|^2) / sigma_i^2``, so one product of a row chunk with the stacked
``[mu_1 .. mu_K | V_1 .. V_K]`` (d x K(q + 1)) serves every component, and the mixture is combined by
log-sum-exp. Rows are shifted by the mixture mean ``sum_i pi_i mu_i`` before the products to limit
cancellation in ``|t|^2 - 2 t.mu + |mu|^2``.

Speed. The E-step constants (Cholesky factors, log-determinants, the stacked projection) are computed once per
fitted parameter set and cached on the estimator (:meth:`MPPCA._projection`). In high dimension most terms of the
log-sum-exp lie hundreds of nats below their row's maximum, where ``exp`` is exactly 0.0 in float64 and numpy's
``exp`` takes a slow path; :func:`_exp` evaluates it only where it can be non-zero, bit for bit the same result.
"""

import logging
import warnings
from typing import NamedTuple

import numpy as np
import scipy.linalg
import scipy.sparse

from voxpose.errors import ConvergenceWarning, VoxposeError
from voxpose.features import mppca_kernels
from voxpose.features.kmeans import DEFAULT_CHUNK_SIZE, KMeans, mean_feature_variance
from voxpose.kernels import use_numba
from voxpose.validation import as_rows, check_fitted, integer

log = logging.getLogger(__name__)

_LOG_2PI = float(np.log(2.0 * np.pi))
_EXP_ZERO = -750.0
"""``exp(x)`` of float64 ``x <= _EXP_ZERO`` is 0.0 (its exact value, below 2^-1082, rounds to zero)."""
_EXP_DENSE = 0.5
"""Above this fraction of entries that may be non-zero, :func:`_exp` evaluates ``np.exp`` everywhere."""
_NEGLIGIBLE = 1e-30
_SPARSE_FRACTION = 0.05


class _Params(NamedTuple):
    """MPPCA parameters: weights (K,), means (K, d), components W (K, d, q), noise variances sigma^2 (K,)."""

    weights: np.ndarray
    means: np.ndarray
    components: np.ndarray
    noise_variance: np.ndarray


class _Projection(NamedTuple):
    """E-step constants of one parameter set (see the module docstring for V_i and L_i).

    offset (d,) the mixture mean subtracted from every row; means (K, d) shifted by it; chol (K, q, q)
    ``L_i``; stack (d + 1, K + K q) in the working dtype,
    ``[[mu_1 .. mu_K, V_1 .. V_K], [-|mu_1|^2 / 2 .. -|mu_K|^2 / 2, -V_1^T mu_1 .. -V_K^T mu_K]]``, so
    that ``[x, 1] @ stack`` gives ``x.mu_i - |mu_i|^2 / 2`` and ``V_i^T (x - mu_i)`` in one product;
    log_norm (K,) ``log pi_i - (d log 2 pi + log|C_i|) / 2``; noise_variance (K,).
    """

    offset: np.ndarray
    means: np.ndarray
    chol: np.ndarray
    stack: np.ndarray
    log_norm: np.ndarray
    noise_variance: np.ndarray


class _Statistics(NamedTuple):
    """Responsibility-weighted sums over all rows, in shifted coordinates ``x = t - offset``.

    counts (K,) ``N_i = sum_n R_ni``; sums (K, d) ``sum_n R_ni x_n``;
    sqdist (K,) ``sum_n R_ni |x_n - mu_i|^2``; cross (K, d, q) ``sum_n R_ni x_n v_ni^T`` and latent (K, q)
    ``sum_n R_ni v_ni`` with ``v_ni = V_i^T (x_n - mu_i)``; log_likelihood the total ``sum_n log p(t_n)``.
    """

    counts: np.ndarray
    sums: np.ndarray
    sqdist: np.ndarray
    cross: np.ndarray
    latent: np.ndarray
    log_likelihood: float


def _project(params, dtype=np.float64):
    """Precompute the E-step constants of ``params``.

    ``dtype`` is the precision of the two large products of the E-step. The estimator always uses float64;
    float32 exists for ``benchmarks/bench_mppca.py``, which measures why it is not offered: on paper-sized
    data it is at most about 1.5x faster, but moves log densities by up to 0.08 and responsibilities by up to
    7e-3 (the ``|x|^2 - 2 x.mu + |mu|^2`` cancellation, divided by sigma^2 ~ 1e-5). The compiled scoring path
    (``_scored_chunks``, ``_accumulate`` with a screen) takes a float32 product only to rule components out, with a
    proven error bound.
    """
    n_components, n_features, n_latent = params.components.shape
    offset = params.weights @ params.means
    means = params.means - offset
    Wt = np.swapaxes(params.components, 1, 2)
    chol = np.linalg.cholesky(params.noise_variance[:, None, None] * np.eye(n_latent) + Wt @ params.components)
    Vt = np.linalg.solve(chol, Wt)  # V_i^T = L_i^-1 W_i^T, shape (K, q, d)
    log_det = (n_features - n_latent) * np.log(params.noise_variance) + 2.0 * np.log(
        np.diagonal(chol, axis1=1, axis2=2)
    ).sum(axis=1)
    stack = np.empty((n_features + 1, n_components * (n_latent + 1)))
    stack[:-1, :n_components] = means.T
    stack[-1, :n_components] = -0.5 * np.einsum("kd,kd->k", means, means)
    stack[:-1, n_components:] = Vt.transpose(2, 0, 1).reshape(n_features, n_components * n_latent)
    stack[-1, n_components:] = -np.einsum("kqd,kd->kq", Vt, means).ravel()
    return _Projection(
        offset=offset,
        means=means,
        chol=chol,
        stack=stack.astype(dtype, copy=False),
        log_norm=np.log(params.weights) - 0.5 * (n_features * _LOG_2PI + log_det),
        noise_variance=params.noise_variance,
    )


def _chunk_products(X, proj, chunk_size):
    """Yield ``(x1, prod, sqnorm)`` per chunk of rows of ``X``: x1 (c, d + 1) float64 shifted rows with a column of
    ones appended, ``prod = x1 @ stack`` (c, K (q + 1)) in the working dtype, sqnorm (c,) the rows' ``|x|^2``."""
    for start in range(0, X.shape[0], chunk_size):
        rows = X[start : start + chunk_size]
        x1 = np.ones((rows.shape[0], rows.shape[1] + 1))
        np.subtract(rows, proj.offset, out=x1[:, :-1])
        yield x1, x1.astype(proj.stack.dtype, copy=False) @ proj.stack, np.einsum("nd,nd->n", x1[:, :-1], x1[:, :-1])


def _log_joint_chunks(X, proj, chunk_size):
    """Yield ``(x1, log_joint, latent, sqdist)`` per chunk of rows of ``X``.

    x1 as ``_chunk_products``; log_joint (c, K) ``log pi_i + log p(t | i)``; latent (c, K, q) ``V_i^T (x - mu_i)``
    in the working dtype; sqdist (c, K) float64 ``|x - mu_i|^2``.
    """
    n_components = proj.means.shape[0]
    n_latent = proj.chol.shape[1]
    for x1, prod, sqnorm in _chunk_products(X, proj, chunk_size):
        sqdist = prod[:, :n_components] * 2.0  # in place from here: each (c, K) temporary costs memory traffic
        np.subtract(sqnorm[:, None], sqdist, out=sqdist)
        latent = prod[:, n_components:].reshape(len(x1), n_components, n_latent)
        log_joint = np.einsum("nkq,nkq->nk", latent, latent)
        np.subtract(sqdist, log_joint, out=log_joint)
        log_joint /= proj.noise_variance  # the Mahalanobis term
        log_joint *= -0.5
        log_joint += proj.log_norm
        yield x1, log_joint, latent, sqdist


def _posterior_chunks(X, proj, chunk_size):
    """Yield ``(x1, resp, log_p, latent, sqdist)`` per chunk of rows of ``X``: the responsibilities (c, K), the log
    density of each row (c,), and ``_log_joint_chunks``'s x1, latent and sqdist (log-sum-exp, then
    ``exp(log joint - log p)``)."""
    for x1, log_joint, latent, sqdist in _log_joint_chunks(X, proj, chunk_size):
        log_p = _logsumexp_rows(log_joint)
        yield x1, _exp(log_joint - log_p[:, None]), log_p, latent, sqdist


class _Screen(NamedTuple):
    """The compiled scoring path's constants of one projection (:mod:`voxpose.features.mppca_kernels`).

    stack32 the projection's stack in float32, its columns in ``mppca_kernels.screen_order``; stack_rows
    (K, d + 1, ``mppca_kernels.padded_width(q)``) each component's stack columns side by side (mean first), then
    zero columns; col_norm (K (q + 1),) the Euclidean norms of stack32's columns, taken in float64; gamma the
    float32 dot product's error factor.
    """

    stack32: np.ndarray
    stack_rows: np.ndarray
    col_norm: np.ndarray
    gamma: float


def _screen(proj):
    """The ``_Screen`` of a float64 projection."""
    n_components, n_latent = proj.chol.shape[:2]
    stack = proj.stack
    rows = np.zeros((n_components, stack.shape[0], mppca_kernels.padded_width(n_latent)))
    rows[:, :, 0] = stack[:, :n_components].T
    latent = stack[:, n_components:].reshape(stack.shape[0], n_components, n_latent)
    rows[:, :, 1 : n_latent + 1] = latent.transpose(1, 0, 2)
    order = mppca_kernels.screen_order(n_components, n_latent)
    screened = stack[:, order]
    return _Screen(screened.astype(np.float32), rows, np.sqrt(np.einsum("ij,ij->j", screened, screened)),
                   mppca_kernels.rounding_factor(stack.shape[0]))  # fmt: skip


def _screened_products(X, proj, screen, chunk_size):
    """Yield ``(x1, prod32)`` per chunk of rows of ``X``: the shifted rows with a column of ones (float64) and their
    float32 product with the stack, the compiled kernels' inputs (:mod:`voxpose.features.mppca_kernels`)."""
    for start in range(0, X.shape[0], chunk_size):
        rows = X[start : start + chunk_size]
        x1 = np.ones((rows.shape[0], rows.shape[1] + 1))
        np.subtract(rows, proj.offset, out=x1[:, :-1])
        yield x1, x1.astype(np.float32) @ screen.stack32


def _scored_chunks(X, proj, screen, chunk_size):
    """Yield ``(resp, log_p, n_kept)`` per chunk of rows of ``X`` by the compiled kernel: a float32 product screens
    the components, the ``n_kept`` (c,) of each row are evaluated in float64 (:mod:`voxpose.features.mppca_kernels`).
    """
    n_latent = proj.chol.shape[1]
    for x1, prod32 in _screened_products(X, proj, screen, chunk_size):
        resp, log_p = np.empty((len(x1), proj.means.shape[0])), np.empty(len(x1))
        n_kept = np.empty(len(x1), dtype=np.int64)
        mppca_kernels.screened_posterior(prod32, x1, screen.stack_rows, screen.col_norm, screen.gamma,
                                         proj.noise_variance, proj.log_norm, n_latent, resp, log_p, n_kept)  # fmt: skip
        yield resp, log_p, n_kept


def _exp(a):
    """``np.exp(a)`` bit for bit, evaluated only where it can be non-zero (``a > _EXP_ZERO``, or NaN).

    For log-sum-exp terms, most of which underflow: numpy's ``exp`` of such arguments is several times slower
    than of ordinary ones (measured 4.7 against 0.6 ms for 819,200 entries, 1 % of them not underflowing).
    """
    live = np.flatnonzero(~(a <= _EXP_ZERO))
    if live.size > _EXP_DENSE * a.size:
        return np.exp(a)
    out = np.zeros_like(a)
    out.flat[live] = np.exp(a.flat[live])
    return out


def _logsumexp_rows(a):
    """``log(sum(exp(a), axis=1))`` without overflow, shape (n,)."""
    peak = a.max(axis=1)
    return peak + np.log(_exp(a - peak[:, None]).sum(axis=1))


def _chunk_moments(x1, resp, latent, sqdist):
    """Sufficient statistics of one chunk: ``(G @ x1 (K (q + 1), d + 1), sum_n R_ni |x_n - mu_i|^2 (K,))``.

    ``G[i (q + 1) + j, n] = R_ni [v_ni, 1]_j``, so ``G @ [x, 1]`` holds every weighted sum the M-step needs.
    Responsibilities below ``_NEGLIGIBLE`` (1e-30) are dropped: they change no sum at float64 resolution.
    In high dimension nearly every row then keeps one component (measured on the benchmark's histogram data,
    d = K = 200: 1.02 per row), so when at most ``_SPARSE_FRACTION`` of the pairs are kept G is built sparse
    from them (measured 14x faster at 0.5 % density); otherwise the dense product is faster.
    """
    n_rows, n_components, n_latent = latent.shape
    kept = resp >= _NEGLIGIBLE
    n_kept = int(np.count_nonzero(kept))
    if n_kept > _SPARSE_FRACTION * resp.size:
        resp = np.where(kept, resp, 0.0)
        G = np.empty((n_rows, n_components, n_latent + 1))
        np.multiply(latent, resp[:, :, None], out=G[:, :, :n_latent])
        G[:, :, n_latent] = resp
        return G.reshape(n_rows, -1).T @ x1, np.einsum("nk,nk->k", resp, sqdist)
    rows, comps = np.nonzero(kept)  # row-major order: G^T is built directly in CSR form
    weight = resp[rows, comps]
    pairs = np.empty((n_kept, n_latent + 1))
    pairs[:, :n_latent] = latent[rows, comps] * weight[:, None]
    pairs[:, n_latent] = weight
    slots = (comps * (n_latent + 1))[:, None] + np.arange(n_latent + 1)
    indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=n_rows) * (n_latent + 1))])
    Gt = scipy.sparse.csr_matrix((pairs.ravel(), slots.ravel(), indptr), shape=(n_rows, n_components * (n_latent + 1)))
    return Gt.T @ x1, np.bincount(comps, weights=weight * sqdist[rows, comps], minlength=n_components)


def _accumulate(X, proj, chunk_size, screen=None):
    """E-step: responsibilities ``R_ni`` of every row and the sufficient statistics of the M-step, chunked.

    With ``screen`` (a ``_Screen`` of ``proj``) the compiled kernel forms them from the screened posterior
    (``mppca_kernels.screened_moments``): the same pairs (``R_ni >= _NEGLIGIBLE``) and sums, to rounding.
    """
    n_components = proj.means.shape[0]
    n_latent = proj.chol.shape[1]
    n_features = X.shape[1]
    moments = np.zeros((n_components * (n_latent + 1), n_features + 1))
    sqdist_sum = np.zeros(n_components)
    total = 0.0
    if screen is not None:
        for x1, prod32 in _screened_products(X, proj, screen, chunk_size):
            total += mppca_kernels.screened_moments(prod32, x1, screen.stack_rows, screen.col_norm, screen.gamma,
                                                    proj.noise_variance, proj.log_norm, n_latent, _NEGLIGIBLE,
                                                    moments, sqdist_sum)  # fmt: skip
    else:
        for x1, resp, log_p, latent, sqdist in _posterior_chunks(X, proj, chunk_size):
            chunk_moments, chunk_sqdist = _chunk_moments(x1, resp, latent, sqdist)
            moments += chunk_moments
            sqdist_sum += chunk_sqdist
            total += float(log_p.sum())
    moments = moments.reshape(n_components, n_latent + 1, n_features + 1)
    return _Statistics(
        counts=moments[:, n_latent, n_features],
        sums=moments[:, n_latent, :n_features],
        sqdist=sqdist_sum,
        cross=moments[:, :n_latent, :n_features].transpose(0, 2, 1),
        latent=moments[:, :n_latent, n_features],
        log_likelihood=total,
    )


def _m_step(stats, proj, params, n_samples, floor):
    """Tipping & Bishop (1999), Appendix C, for every component at once; returns the new params.

    ``pi_i = N_i / N``, ``mu_i = sum_n R_ni t_n / N_i``, and from the responsibility-weighted covariance about
    the new mean, ``S_i = sum_n R_ni (t_n - mu_i)(t_n - mu_i)^T / N_i``, the one-step updates
    ``W~_i = S_i W_i (sigma_i^2 I + M_i^-1 W_i^T S_i W_i)^-1`` and
    ``sigma~_i^2 = tr(S_i - S_i W_i M_i^-1 W~_i^T) / d``, floored at ``floor``. ``S_i`` is never formed: only
    ``S_i W_i`` (d x q) and ``tr S_i`` are, from statistics taken about the old mean ``m``:
    ``N_i S_i W_i = [sum_n R_ni (t_n - m) v_ni^T] L_i^T - N_i delta (delta^T W_i)`` with ``delta = mu_i - m``.
    ``W~`` uses ``(sigma^2 I + M^-1 A)^-1 = (sigma^2 M + A)^-1 M`` so only symmetric positive definite systems
    are solved. A component with ``N_i < 1`` (less than one row of evidence) keeps its old mean, W and
    sigma^2; the caller re-seeds it.
    """
    n_latent = params.components.shape[2]
    n_features = params.means.shape[1]
    keep = stats.counts >= 1.0
    counts = stats.counts[keep]
    W = params.components[keep]
    noise = params.noise_variance[keep]
    means = stats.sums[keep] / counts[:, None]
    delta = means - proj.means[keep]
    scatter_v = stats.cross[keep] - proj.means[keep][:, :, None] * stats.latent[keep][:, None, :]
    SW = (scatter_v @ np.swapaxes(proj.chol[keep], 1, 2)) / counts[:, None, None]
    SW -= delta[:, :, None] * np.einsum("kd,kdq->kq", delta, W)[:, None, :]
    trace_S = stats.sqdist[keep] / counts - np.einsum("kd,kd->k", delta, delta)
    Wt = np.swapaxes(W, 1, 2)
    M = noise[:, None, None] * np.eye(n_latent) + Wt @ W
    WSW = Wt @ SW
    B = noise[:, None, None] * M + 0.5 * (WSW + np.swapaxes(WSW, 1, 2))
    SWt = np.swapaxes(SW, 1, 2)
    W_new_t = M @ np.linalg.solve(B, SWt)
    noise_new = (trace_S - np.einsum("kqd,kqd->k", np.linalg.solve(M, SWt), W_new_t)) / n_features

    new_means = params.means.copy()
    new_means[keep] = means + proj.offset
    components = params.components.copy()
    components[keep] = np.swapaxes(W_new_t, 1, 2)
    noise_variance = params.noise_variance.copy()
    noise_variance[keep] = np.maximum(noise_new, floor)
    return _Params(stats.counts / n_samples, new_means, components, noise_variance)


def _reseed(params, starved, rng):
    """Re-seed each starved component by splitting the currently heaviest one; returns new params.

    The heaviest component j is halved in weight and its mean moved by ``-/+ sqrt(2/pi) s u`` for itself and
    the re-seeded slot, where u is the leading principal direction of ``C_j`` and ``s^2`` its variance (the
    means of the two halves of a Gaussian cut through its centre); W and sigma^2 are copied. With q = 0 the
    direction is drawn at random from ``rng``. Weights are renormalised to sum to one.
    """
    weights, means = params.weights.copy(), params.means.copy()
    components, noise = params.components.copy(), params.noise_variance.copy()
    for i in np.flatnonzero(starved):
        weights[i] = 0.0
        j = int(np.argmax(weights))
        if components.shape[2]:
            u, s, _ = np.linalg.svd(components[j], full_matrices=False)
            direction, variance = u[:, 0], s[0] ** 2 + noise[j]
        else:
            direction = rng.standard_normal(means.shape[1])
            direction, variance = direction / np.linalg.norm(direction), noise[j]
        shift = np.sqrt(2.0 / np.pi * variance) * direction
        means[i], means[j] = means[j] + shift, means[j] - shift
        weights[i] = weights[j] = weights[j] / 2.0
        components[i], noise[i] = components[j], noise[j]
    return _Params(weights / weights.sum(), means, components, noise)


def _ppca_from_covariance(cov, n_latent):
    """Closed-form maximum-likelihood PPCA of a covariance (Tipping & Bishop 1999): (W (d, q), sigma^2).

    ``sigma^2`` is the mean of the d - q smallest eigenvalues, ``(tr C - sum of the q largest) / (d - q)``,
    and ``W = U_q (Lambda_q - sigma^2 I)^(1/2)``. Only the q leading eigenpairs are computed (LAPACK syevr).
    """
    n_features = cov.shape[0]
    if n_latent == 0:
        return np.zeros((n_features, 0)), max(float(np.trace(cov)) / n_features, 0.0)
    eigval, eigvec = scipy.linalg.eigh(cov, subset_by_index=[n_features - n_latent, n_features - 1])
    noise = max((float(np.trace(cov)) - float(eigval.sum())) / (n_features - n_latent), 0.0)
    return eigvec * np.sqrt(np.maximum(eigval - noise, 0.0)), noise


def _initialise(X, n_components, n_latent, chunk_size, rng):
    """k-means, then the maximum-likelihood PPCA of each cluster's covariance; returns (params, starved).

    Weights are the cluster fractions and means the cluster means. Clusters with fewer than q + 1 rows are
    starved: their W and sigma^2 are left at zero for the caller to re-seed.
    """
    n_samples, n_features = X.shape
    kmeans = KMeans(n_components, chunk_size=chunk_size, random_state=rng).fit(X)
    counts = np.bincount(kmeans.labels_, minlength=n_components)
    order = np.argsort(kmeans.labels_, kind="stable")
    bounds = np.concatenate([[0], np.cumsum(counts)])
    means = kmeans.cluster_centers_.copy()
    components = np.zeros((n_components, n_features, n_latent))
    noise = np.zeros(n_components)
    starved = counts < n_latent + 1
    for k in np.flatnonzero(~starved):
        rows = order[bounds[k] : bounds[k + 1]]
        centre = kmeans.cluster_centers_[k]
        first = np.zeros(n_features)
        scatter = np.zeros((n_features, n_features))
        for start in range(0, rows.size, chunk_size):
            y = np.asarray(X[rows[start : start + chunk_size]], dtype=np.float64) - centre
            first += y.sum(axis=0)
            scatter += y.T @ y
        shift = first / counts[k]
        means[k] = centre + shift
        components[k], noise[k] = _ppca_from_covariance(scatter / counts[k] - np.outer(shift, shift), n_latent)
    return _Params(counts / n_samples, means, components, noise), starved


class MPPCA:
    """Mixture of probabilistic PCA (Tipping & Bishop 1999) fitted by EM, as in Sun et al. (2006), Sec. 5.

    Parameters
    ----------
    n_components : int
        Number of PPCA components K; Sun et al. choose K = 200 by cross-validation (Sec. 6, Fig. 4).
    n_latent : int
        Latent dimension q of every component, ``0 <= q < d``. Sun et al. do not state q; 10 is our default.
        With q = 0 the model is a mixture of spherical Gaussians.
    max_iter : int
        Maximum number of EM iterations (M-steps); 0 keeps the initialisation.
    tol : float
        EM stops when the mean log-likelihood per row changes by at most ``tol * |previous value|``. This
        relative test depends on the units of the data: scaling the rows by c shifts the mean log-likelihood
        by ``-d log c`` but leaves its changes alone.
    init : {"kmeans"}
        Initialisation: seeded k-means++ / Lloyd (:class:`voxpose.features.kmeans.KMeans`, default settings), then the
        maximum-likelihood PPCA of each cluster's covariance (W from its top q eigenvectors, sigma^2 the mean
        discarded eigenvalue) and the cluster fractions as weights.
    chunk_size : int
        Rows processed at once. Memory is O(K d q) for the statistics plus about ``chunk_size * K * (q + 1)``
        floats of work space; a d x d covariance is formed only during initialisation, one cluster at a time.
    min_noise_variance : float
        Floor on every sigma_i^2, relative to the mean per-feature variance of the training data (the absolute
        floor is stored as ``noise_variance_floor_``). It keeps a component that collapses onto identical rows
        from driving the likelihood to infinity.
    random_state : int, numpy Generator or None
        Seed of the k-means++ draws and of the (q = 0) re-seeding directions.
    compiled : bool
        ``fit``'s E-step, ``score_samples``, ``predict_proba`` and ``proba_and_score`` run the compiled kernels
        (:mod:`voxpose.features.mppca_kernels`, when :mod:`voxpose.kernels` allows it): a float32 product screens
        out the components whose responsibility is provably below 1e-30 (they get 0; the E-step drops those
        anyway), the rest are evaluated in float64, so the numbers are the numpy path's to rounding and to 1e-30.
        Off by default: numba's start-up (about 0.5 s per process) repays only in processes that evaluate many
        rows: the feature fit (``FeatureModel.fit_rows``; every row in every EM iteration), ``voxpose features``
        and ``voxpose predict`` (``FeatureModel.compiled``).

    Attributes
    ----------
    weights_ : ndarray, shape (K,)
        Mixing proportions pi_i.
    means_ : ndarray, shape (K, d)
    components_ : ndarray, shape (K, d, q)
        The W_i matrices (unique only up to a rotation of the latent space).
    noise_variance_ : ndarray, shape (K,)
        sigma_i^2.
    noise_variance_floor_ : float
    log_likelihood_ : list of float
        Mean log-likelihood per row of the training data: entry 0 for the initialisation, entry t after
        M-step t; the last entry belongs to the returned parameters, so it equals ``score(X)``.
    n_iter_ : int
        Number of M-steps performed.
    converged_ : bool
    n_reseeded_ : int
        Count of starved components (``N_i < q + 1``) re-seeded during initialisation and EM.
    n_features_in_ : int

    Notes
    -----
    EM follows Tipping & Bishop (1999), Appendix C: the responsibilities ``R_ni`` of the E-step feed the
    updates of pi_i and mu_i and then the one-step updates of W_i and sigma_i^2 from the local covariance
    ``S_i`` taken about the new mean (see :func:`_m_step`). This is a generalised EM step: for the fixed
    posteriors ``R``, pi and mu maximise the expected complete-data log-likelihood and the W, sigma^2
    update is one EM step of the responsibility-weighted PPCA sub-problem (a floored sigma^2 is its
    constrained maximiser), so the log-likelihood never decreases beyond round-off.

    A component is starved when its share ``N_i = sum_n R_ni`` falls below q + 1 rows, too few to fit a
    q-dimensional subspace; it is re-seeded by splitting the heaviest component (:func:`_reseed`). A split is
    not a likelihood-ascent step: the likelihood may drop at that iteration, and convergence is never
    declared on it. Each slot is re-seeded at most once for ``1 <= N_i < q + 1``: a genuine outlier (a few
    rows far from the rest) attracts some component back every few iterations, and re-seeding again would
    only cycle, so a slot that starves a second time keeps modelling its few rows (its sigma^2 held up by
    the floor). A slot with ``N_i < 1`` cannot be estimated and is always re-seeded.
    """

    def __init__(
        self,
        n_components=200,
        *,
        n_latent=10,
        max_iter=100,
        tol=1e-4,
        init="kmeans",
        chunk_size=DEFAULT_CHUNK_SIZE,
        min_noise_variance=1e-6,
        random_state=None,
        compiled=False,
    ):
        self.n_components = n_components
        self.n_latent = n_latent
        self.max_iter = max_iter
        self.tol = tol
        self.init = init
        self.chunk_size = chunk_size
        self.min_noise_variance = min_noise_variance
        self.random_state = random_state
        self.compiled = compiled

    def _check_params(self, n_samples, n_features):
        """Validate the hyper-parameters against the data shape; return the chunk size."""
        integer(self.n_components, "n_components")
        if integer(self.n_latent, "n_latent", minimum=0) >= n_features:
            raise VoxposeError(
                f"n_latent must be an integer with 0 <= n_latent < {n_features} (the data dimension), "
                f"got {self.n_latent!r}"
            )
        needed = self.n_components * (self.n_latent + 1)
        if n_samples < needed:
            raise VoxposeError(
                f"MPPCA with {self.n_components} components of latent dimension {self.n_latent} needs at "
                f"least {needed} rows (q + 1 per component), got {n_samples}"
            )
        integer(self.max_iter, "max_iter", minimum=0)
        if not np.isfinite(self.tol) or self.tol < 0:
            raise VoxposeError(f"tol must be a non-negative number, got {self.tol!r}")
        if self.init != "kmeans":
            raise VoxposeError(f"init must be 'kmeans', got {self.init!r}")
        if not np.isfinite(self.min_noise_variance) or self.min_noise_variance <= 0:
            raise VoxposeError(f"min_noise_variance must be a positive number, got {self.min_noise_variance!r}")
        return integer(self.chunk_size, "chunk_size")

    def fit(self, X):
        """Fit the mixture to the rows of ``X`` (n_samples, d) by EM; returns ``self``."""
        X = as_rows(X, "MPPCA training data", dtype=None)
        n_samples, n_features = X.shape
        chunk = self._check_params(n_samples, n_features)
        rng = np.random.default_rng(self.random_state)
        variance = mean_feature_variance(X, chunk)
        if variance <= 0.0:
            raise VoxposeError("MPPCA training data has zero variance (all rows are identical)")
        floor = self.min_noise_variance * variance
        log.info(
            "MPPCA: %d components, latent dimension %d, %d rows of dimension %d",
            self.n_components,
            self.n_latent,
            n_samples,
            n_features,
        )
        params, reseeded = _initialise(X, self.n_components, self.n_latent, chunk, rng)
        params = params._replace(noise_variance=np.maximum(params.noise_variance, floor))
        n_reseeded = int(reseeded.sum())
        if n_reseeded:
            params = _reseed(params, reseeded, rng)
            log.info("MPPCA initialisation: re-seeded %d starved components", n_reseeded)
        screened = self.compiled and use_numba()
        proj = _project(params)
        stats = _accumulate(X, proj, chunk, _screen(proj) if screened else None)
        history = [stats.log_likelihood / n_samples]
        log.info("MPPCA initialisation: mean log-likelihood %.6f", history[0])
        n_iter, converged = 0, False
        while n_iter < self.max_iter and not converged:
            n_iter += 1
            starved = (stats.counts < 1.0) | ((stats.counts < self.n_latent + 1) & ~reseeded)
            params = _m_step(stats, proj, params, n_samples, floor)
            if starved.any():
                n_reseeded += int(starved.sum())
                reseeded |= starved
                params = _reseed(params, starved, rng)
            proj = _project(params)
            stats = _accumulate(X, proj, chunk, _screen(proj) if screened else None)
            history.append(stats.log_likelihood / n_samples)
            change = history[-1] - history[-2]
            converged = not starved.any() and abs(change) <= self.tol * abs(history[-2])
            log.info(
                "MPPCA EM iteration %d: mean log-likelihood %.6f (change %+.3g)%s",
                n_iter,
                history[-1],
                change,
                f", re-seeded {int(starved.sum())}" if starved.any() else "",
            )
        self._set_params(params)
        self.noise_variance_floor_ = floor
        self.log_likelihood_ = history
        self.n_iter_ = n_iter
        self.converged_ = converged
        self.n_reseeded_ = n_reseeded
        self.n_features_in_ = n_features
        if not converged and self.max_iter > 0:
            warnings.warn(f"MPPCA: no convergence in {n_iter} EM iterations (tol {self.tol:g})", ConvergenceWarning, 2)
        log.info(
            "MPPCA: %d EM iterations, converged: %s, %d components re-seeded, mean log-likelihood %.6f",
            n_iter,
            converged,
            n_reseeded,
            history[-1],
        )
        return self

    def to_arrays(self) -> tuple[dict, dict]:
        """The fitted mixture as (arrays, meta), the feature model's stored form; ``from_arrays`` inverts it."""
        check_fitted(self, "components_")
        arrays = {"weights": self.weights_, "means": self.means_, "components": self.components_,
                  "noise_variance": self.noise_variance_}  # fmt: skip
        meta = {"log_likelihood": self.log_likelihood_, "n_iter": self.n_iter_, "converged": self.converged_,
                "n_reseeded": self.n_reseeded_, "noise_variance_floor": self.noise_variance_floor_}  # fmt: skip
        return arrays, meta

    @classmethod
    def from_arrays(cls, arrays: dict, meta: dict) -> "MPPCA":
        """The MPPCA that ``to_arrays`` recorded, fitted: it scores and predicts as the original did.

        ``n_components`` and ``n_latent`` follow from the arrays' shapes; the other hyper-parameters, which
        only matter to ``fit``, are the defaults.
        """
        n_components, n_features, n_latent = np.shape(arrays["components"])
        model = cls(n_components, n_latent=n_latent)
        model._set_params(_Params(arrays["weights"], arrays["means"], arrays["components"], arrays["noise_variance"]))
        model.noise_variance_floor_ = meta["noise_variance_floor"]
        model.log_likelihood_, model.n_iter_ = list(meta["log_likelihood"]), meta["n_iter"]
        model.converged_, model.n_reseeded_ = meta["converged"], meta["n_reseeded"]
        model.n_features_in_ = n_features
        return model

    def _set_params(self, params):
        """Store fitted parameters as read-only copies, so that they change only by being replaced (which
        :meth:`_projection` notices)."""
        frozen = []
        for array in params:
            array = np.array(array)
            array.flags.writeable = False
            frozen.append(array)
        self.weights_, self.means_, self.components_, self.noise_variance_ = frozen

    def _projection(self):
        """The E-step constants of the fitted parameters, computed once per parameter set (cached on the
        estimator, keyed on the parameter arrays themselves: replacing one recomputes them)."""
        params = _Params(self.weights_, self.means_, self.components_, self.noise_variance_)
        cached = self.__dict__.get("_projection_cache")
        if cached is None or any(new is not old for new, old in zip(params, cached[0], strict=True)):
            cached = self._projection_cache = (params, _project(params))
        return cached[1]

    def _screening(self):
        """The compiled scoring path's constants (``_Screen``), computed once per parameter set like
        :meth:`_projection`."""
        proj = self._projection()
        cached = self.__dict__.get("_screen_cache")
        if cached is None or cached[0] is not proj:
            cached = self._screen_cache = (proj, _screen(proj))
        return cached[1]

    def _scoring_setup(self, X):
        """Validate ``X`` against the fitted model; return (X, projection, chunk size)."""
        check_fitted(self, "components_")
        X = as_rows(X, "MPPCA input", self.n_features_in_, dtype=None)
        return X, self._projection(), integer(self.chunk_size, "chunk_size")

    def _posteriors(self, X, proj, chunk):
        """``(resp, log_p)`` per chunk: the compiled screened kernel with ``compiled`` (and the kernels enabled),
        else the numpy path."""
        if self.compiled and use_numba():
            return ((resp, log_p) for resp, log_p, _ in _scored_chunks(X, proj, self._screening(), chunk))
        return ((resp, log_p) for _, resp, log_p, _, _ in _posterior_chunks(X, proj, chunk))

    def score_samples(self, X):
        """Log density ``log p(t_n)`` of each row of ``X`` (n, d) under the mixture: shape (n,)."""
        X, proj, chunk = self._scoring_setup(X)
        if self.compiled and use_numba():
            return np.concatenate([log_p for _, log_p in self._posteriors(X, proj, chunk)])
        return np.concatenate([_logsumexp_rows(lj) for _, lj, _, _ in _log_joint_chunks(X, proj, chunk)])

    def score(self, X):
        """Mean log density per row of ``X`` (n, d)."""
        return float(self.score_samples(X).mean())

    def predict_proba(self, X):
        """Responsibilities ``p(i | t_n)`` of each component for each row of ``X`` (n, d): shape (n, K)."""
        return self.proba_and_score(X)[0]

    def proba_and_score(self, X):
        """``(predict_proba(X), score_samples(X))`` from one evaluation of the log joint: the responsibilities
        are normalised by the log density anyway."""
        X, proj, chunk = self._scoring_setup(X)
        proba, score = [], []
        for resp, log_p in self._posteriors(X, proj, chunk):
            proba.append(resp)
            score.append(log_p)
        return np.concatenate(proba), np.concatenate(score)
