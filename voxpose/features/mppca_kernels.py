"""Compiled (numba) kernels of the MPPCA's posterior, for scoring and for the EM's E-step
(:class:`voxpose.features.mppca.MPPCA` with ``compiled=True``), selected by :mod:`voxpose.kernels`: a float32
product screens the components, float64 decides.

The numpy path evaluates every component of every row from one float64 product ``[x, 1] @ stack``
(``voxpose.features.mppca``, module docstring), (d + 1) x K (q + 1) multiply-adds per row, the most of a predicted
frame's feature time. Nearly all of those terms are irrelevant: on the default run's descriptors a row has 2.0
components within 100 nats of its best one, of K = 200. This kernel takes the same product in float32 (``prod32``,
about half the time in BLAS), and per row

1. bounds each component's log joint from it: ``approx +- err``, where ``err`` follows from the rounding error of a
   float32 dot product, ``|fl(a . b) - a . b| <= gamma |a| |b|`` with ``gamma = (n + 2) u / (1 - (n + 2) u)``,
   ``u = 2^-24`` and n = d + 1 terms (Higham, *Accuracy and Stability of Numerical Algorithms*, Sec. 3.1; the two
   extra units cover rounding the inputs to float32; any summation order, fused or not; plus 2^-120 for
   underflow), carried through
   ``|x - mu|^2 = |x|^2 - 2 (x . mu - |mu|^2 / 2)`` and the latent norm ``sum_j p_j^2`` (for a computed ``p^`` with
   error at most ``e``, ``|p^2 - p^^2| <= e (2 |p^| + e)``), with a relative slack of 1e-9 for the float64 arithmetic;
2. keeps the components whose upper bound reaches ``best lower bound - SCREEN_NATS``: any other has a responsibility
   below ``exp(-SCREEN_NATS) = 1e-30`` (``voxpose.features.mppca._NEGLIGIBLE``, the level below which the EM already
   drops responsibilities as changing no sum at float64 resolution), and is given exactly 0;
3. evaluates the kept components in float64 from the rows and the stacked projection, ``(d + 1) (q + 1)`` multiply-
   adds each, and combines them as before: ``exp(l_i - peak) / sum_j exp(l_j - peak)``, terms more than 750 nats
   below the peak exactly 0, ``log p = peak + log(sum)``.

So the kept responsibilities and the log density equal the numpy path's to rounding (the tests compare to 1e-12),
and a screened one differs from it by less than 1e-30. A row whose bounds are not finite (NaN or overflowing input)
is evaluated in full, as the numpy path would. ``screened_moments`` adds up the E-step's sufficient statistics of
the kept pairs with responsibility at least 1e-30 (the pairs the numpy E-step keeps) straight from the float64
evaluation: on a default run's MPPCA and 20,000 of its training descriptors, statistics within 7.4e-15 of the
numpy path's (relative to each one's largest entry) and an E-step of 0.216 s of CPU instead of 0.362 s (0.60x,
one core; ``benchmarks/bench_mppca_screen.py``).

Step 1 runs component-wise over the float32 product laid out by latent coordinate (``screen_order``), so each of
its loops is a flat pass over the K components that the compiler vectorises, and steps 2-3 visit only the kept
components: the same numbers bit for bit (features and feature models of a default run compared), 0.87x the
scoring time and 0.85x the E-step's of the component-by-component loops before (``bench_mppca_screen.py``,
alternated: 2.32 -> 2.02-2.04 CPU ms per 240 rows, E-step 0.193 -> 0.162-0.164 s).
"""

import math

import numpy as np

from voxpose.kernels import jit

_EXP_ZERO = -750.0  # as voxpose.features.mppca._EXP_ZERO: exp of anything at or below it is 0.0 in float64
SCREEN_NATS = 69.08
"""Components whose log joint is provably this far below a row's best are screened out: ``exp(-69.08) < 1e-30``."""
_UNIT = 2.0**-24  # float32 unit round-off
_SLACK = 1e-9  # relative allowance for the float64 arithmetic of the bounds themselves
_TINY = 2.0**-120  # absolute allowance per dot product for float32 underflow (at most d + 3 terms of 2^-150)
ACCUMULATORS = 8  # the exact evaluation's local accumulators (``_exact_joint``)


def screen_order(n_components: int, n_latent: int) -> np.ndarray:
    """The screen's column order of the projection's stack (K means, then K blocks of q: component k's latent
    coordinate j at ``K + k q + j``): the means, then q blocks of K, so that block j holds every component's
    coordinate j and ``_row_terms`` bounds all components in flat loops."""
    latent = n_components + np.arange(n_components * n_latent).reshape(n_components, n_latent).T.ravel()
    return np.concatenate([np.arange(n_components), latent])


def padded_width(n_latent: int) -> int:
    """Columns of ``stack_rows`` per component: the q + 1 of the exact evaluation, padded with zero columns to a
    multiple of ``ACCUMULATORS`` (``_exact_joint``)."""
    return ACCUMULATORS * -(-(n_latent + 1) // ACCUMULATORS)


def rounding_factor(n_terms: int) -> float:
    """``gamma`` of the module docstring for float32 dot products of ``n_terms`` terms with rounded inputs."""
    nu = (n_terms + 2) * _UNIT
    return nu / (1.0 - nu)


@jit
def _exact_joint(x1, row, stack_rows, k, sqnorm, noise_variance, log_norm, n_latent, acc):  # pragma: no cover
    """The float64 log joint of component ``k`` for row ``row`` of ``x1``, as the numpy path computes it; ``acc``
    (q + 1,) receives ``x . mu_k - |mu_k|^2 / 2`` and the latent coordinates ``V_k^T (x - mu_k)``.

    Each of those q + 1 sums runs over ``x1``'s columns in order, eight at a time in local accumulators (``stack_rows``
    is padded with zero columns to a multiple of ``ACCUMULATORS``, ``padded_width``): the same additions in the same
    order as one accumulator array in memory, so the same bits, without a store and a reload per term (measured in
    ``benchmarks/bench_mppca_screen.py``'s docstring)."""
    for j0 in range(0, stack_rows.shape[2], ACCUMULATORS):
        a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = 0.0
        for i in range(x1.shape[1]):
            xi = x1[row, i]
            a0 += xi * stack_rows[k, i, j0]
            a1 += xi * stack_rows[k, i, j0 + 1]
            a2 += xi * stack_rows[k, i, j0 + 2]
            a3 += xi * stack_rows[k, i, j0 + 3]
            a4 += xi * stack_rows[k, i, j0 + 4]
            a5 += xi * stack_rows[k, i, j0 + 5]
            a6 += xi * stack_rows[k, i, j0 + 6]
            a7 += xi * stack_rows[k, i, j0 + 7]
        sums = (a0, a1, a2, a3, a4, a5, a6, a7)
        for j in range(min(ACCUMULATORS, n_latent + 1 - j0)):
            acc[j0 + j] = sums[j]
    latent = 0.0
    for j in range(1, n_latent + 1):
        latent += acc[j] * acc[j]
    dist = sqnorm - acc[0] * 2.0
    return (dist - latent) / noise_variance[k] * -0.5 + log_norm[k]


@jit
def _row_terms(prod32, x1, i, stack_rows, col_norm, gamma, noise_variance, inverse, log_norm, n_latent, kept, accs,
               terms, bound):  # fmt: skip  # pragma: no cover (compiled)
    """Screen and evaluate row ``i`` (steps 1-3 of the module docstring): ``kept[:n]`` (of K) the components
    evaluated in float64, in increasing order, ``accs`` (K, q + 1) their ``_exact_joint`` products, ``terms`` (K,)
    ``exp(l_k - peak)`` (0 for the others), ``bound`` (K,) scratch; ``inverse`` (K,) ``0.5 / sigma_k^2``. Returns
    ``(|x|^2, peak, sum of terms, n)``.

    The bounds are formed component-wise in flat loops over k, one per latent coordinate (``prod32``'s columns
    are grouped by coordinate, ``screen_order``), which the compiler vectorises; the approximate log joint sums
    the latent squares in the same order as ``_exact_joint``.
    """
    n_components = log_norm.shape[0]
    sqnorm = 0.0
    for t in range(x1.shape[1] - 1):
        sqnorm += x1[i, t] * x1[i, t]
    scale = gamma * math.sqrt(sqnorm + 1.0)  # |[x, 1]| times gamma
    for k in range(n_components):  # terms: the latent norm so far; bound: the error terms (not yet scaled)
        p_mean = np.float64(prod32[i, k])
        terms[k] = 0.0
        bound[k] = 2.0 * (scale * col_norm[k] + _TINY) + _SLACK * (sqnorm + 2.0 * abs(p_mean))
    for j in range(n_latent):
        base = n_components * (j + 1)
        for k in range(n_components):
            p = np.float64(prod32[i, base + k])
            e = scale * col_norm[base + k] + _TINY
            square = p * p
            terms[k] += square
            bound[k] += e * (2.0 * abs(p) + e) + _SLACK * square
    for k in range(n_components):  # terms: the approximate log joint, bound: its error bound
        terms[k] = -(sqnorm - 2.0 * np.float64(prod32[i, k]) - terms[k]) * inverse[k] + log_norm[k]
        bound[k] = bound[k] * inverse[k] + _SLACK * abs(log_norm[k])
    best_lower = -np.inf
    finite = True
    for k in range(n_components):
        if not (math.isfinite(terms[k]) and math.isfinite(bound[k])):
            finite = False
        elif terms[k] - bound[k] > best_lower:
            best_lower = terms[k] - bound[k]
    cut = best_lower - SCREEN_NATS
    n_kept = 0
    for k in range(n_components):
        if not finite or terms[k] + bound[k] >= cut:
            kept[n_kept] = k
            n_kept += 1
        terms[k] = 0.0
    peak = -np.inf
    for m in range(n_kept):  # bound: the kept components' log joints
        k = kept[m]
        bound[k] = _exact_joint(x1, i, stack_rows, k, sqnorm, noise_variance, log_norm, n_latent, accs[k])
        if bound[k] > peak:
            peak = bound[k]
    total = 0.0
    for m in range(n_kept):  # in increasing k, as a sum over all K with the screened terms 0
        k = kept[m]
        shifted = bound[k] - peak
        terms[k] = math.exp(shifted) if shifted > _EXP_ZERO else 0.0
        total += terms[k]
    return sqnorm, peak, total, n_kept


@jit
def screened_posterior(prod32, x1, stack_rows, col_norm, gamma, noise_variance, log_norm, n_latent, resp, log_p,
                       n_kept):  # fmt: skip  # pragma: no cover (compiled)
    """Fill ``resp`` (c, K), ``log_p`` (c,) and ``n_kept`` (c,), the components evaluated in float64 per row, for the
    rows ``x1`` (c, d + 1, shifted, with the column of ones).

    ``prod32`` (c, K (q + 1)) float32 ``x1 @ stack`` in the screen's column order (``screen_order``: K means, then
    q blocks of K, block j holding every component's latent coordinate j); ``stack_rows`` (K, d + 1, w)
    float64, component k's q + 1 columns side by side (mean first), then zero columns up to ``w = padded_width(q)``;
    ``col_norm`` (K (q + 1),) the Euclidean norms of the stack's columns in the screen's order; ``gamma`` from
    ``rounding_factor(d + 1)``.
    """
    n_components = log_norm.shape[0]
    kept = np.empty(n_components, dtype=np.int64)
    accs = np.empty((n_components, n_latent + 1))
    bound = np.empty(n_components)
    inverse = 0.5 / noise_variance
    for i in range(prod32.shape[0]):
        _, peak, total, count = _row_terms(prod32, x1, i, stack_rows, col_norm, gamma, noise_variance, inverse,
                                           log_norm, n_latent, kept, accs, resp[i], bound)  # fmt: skip
        n_kept[i] = count
        log_p[i] = peak + math.log(total)
        inverse_total = 1.0 / total
        for k in range(n_components):
            resp[i, k] *= inverse_total


@jit
def screened_moments(prod32, x1, stack_rows, col_norm, gamma, noise_variance, log_norm, n_latent, negligible,
                     moments, sqdist):  # fmt: skip  # pragma: no cover (compiled)
    """The EM's sufficient statistics of the rows ``x1`` from the screened posterior, added to ``moments``
    (K (q + 1), d + 1) and ``sqdist`` (K,) as ``voxpose.features.mppca._chunk_moments`` forms them: row
    ``k (q + 1) + j`` of ``moments`` sums ``R_nk v_nkj [x_n, 1]`` (j < q) and ``R_nk [x_n, 1]`` (j = q), ``sqdist[k]``
    sums ``R_nk |x_n - mu_k|^2``, over the pairs with ``R_nk >= negligible``. Returns the rows' summed log density.
    Arguments otherwise as ``screened_posterior``."""
    n_components = log_norm.shape[0]
    n_cols = x1.shape[1]
    kept = np.empty(n_components, dtype=np.int64)
    accs = np.empty((n_components, n_latent + 1))
    terms = np.empty(n_components)
    bound = np.empty(n_components)
    inverse = 0.5 / noise_variance
    total_log_p = 0.0
    for i in range(prod32.shape[0]):
        sqnorm, peak, total, n_kept = _row_terms(prod32, x1, i, stack_rows, col_norm, gamma, noise_variance, inverse,
                                            log_norm, n_latent, kept, accs, terms, bound)  # fmt: skip
        total_log_p += peak + math.log(total)
        inverse_total = 1.0 / total
        for m in range(n_kept):
            k = kept[m]
            weight = terms[k] * inverse_total
            if not weight >= negligible:
                continue
            base = k * (n_latent + 1)
            for j in range(n_latent):
                g = accs[k, j + 1] * weight
                for t in range(n_cols):
                    moments[base + j, t] += g * x1[i, t]
            for t in range(n_cols):
                moments[base + n_latent, t] += weight * x1[i, t]
            sqdist[k] += weight * (sqnorm - accs[k, 0] * 2.0)
    return total_log_p
