"""The Multi-Variate Relevance Vector Machine of Section 3 (Eqs. 2-3), trained by fast marginal-likelihood
maximisation.

Model (Thayananthan et al. 2006, "Multivariate relevance vector machines for tracking", ECCV): P outputs
``y = W phi(x) + xi`` (Eq. 2) with the basis ``phi`` of Eq. 3 (a bias and one Gaussian per training row,
``voxpose.regression.kernels``); noise ``xi_p ~ N(0, 1/beta_p)``, one precision per output (Eq. 2's diagonal
covariance); weights ``w_mp ~ N(0, 1/alpha_m)``, one precision per basis function *shared by all P
outputs*, so a basis function is relevant for all outputs or for none and the model keeps one set of
relevance vectors (the "zero columns of W" of Section 3).

Marginal likelihood. For fixed ``alpha`` and ``beta`` the outputs are independent:
``L = sum_p L_p``, ``L_p = -1/2 [N log 2 pi + log|C_p| + y_p' C_p^-1 y_p]``,
``C_p = beta_p^-1 I + Phi A^-1 Phi'`` over the active basis functions. Because ``beta_p`` differs per
output, so do the posterior ``Sigma_p = (A + beta_p Phi'Phi)^-1``, ``mu_p = beta_p Sigma_p Phi' y_p`` and
the sparsity and quality factors of Tipping & Faul (2003, Sec. 3), which we keep exactly, per output:

    S_mp = phi_m' C_p^-1 phi_m = beta_p phi_m'phi_m - beta_p^2 phi_m' Phi Sigma_p Phi' phi_m,
    Q_mp = phi_m' C_p^-1 y_p   = beta_p phi_m'y_p   - beta_p   phi_m' Phi mu_p,
    s_mp = alpha_m S_mp / (alpha_m - S_mp),  q_mp = alpha_m Q_mp / (alpha_m - S_mp)   (active m),
    s_mp = S_mp, q_mp = Q_mp                                                          (inactive m).

(With one shared ``beta``, ``s_m`` would be the same for all outputs up to the factor ``beta``; with one
``beta_p`` per output it is not, since ``Sigma_p`` itself depends on ``beta_p``.) Tipping & Faul's
decomposition of ``log|C_p|`` and ``C_p^-1`` (their Sec. 3) applies output by output, so the part of
``L`` that depends on ``alpha_m`` is

    l_m(alpha) = sum_p 1/2 [log alpha - log(alpha + s_mp) + q_mp^2 / (alpha + s_mp)],   l_m(inf) = 0,

and changing ``alpha_m`` alone changes ``L`` by exactly ``l_m(new) - l_m(old)``. Its stationary points
solve ``sum_p [s_mp^2 + alpha (s_mp - q_mp^2)] / (alpha + s_mp)^2 = 0``; times ``prod_p (alpha + s_mp)^2``
this is a polynomial of degree ``2P - 1``. ``optimal_alpha`` takes its real positive roots (eigenvalues
of the companion matrix of the polynomial in ``alpha`` over the geometric mean of the ``s_mp``, Newton-
polished) together with the P single-output optima ``s^2 / (q^2 - s)`` and ``alpha = inf`` as
candidates, and keeps the one with the largest ``l`` evaluated directly, so the choice never rests on a
root's accuracy alone. For P = 1 it is Tipping & Faul's ``alpha = s^2 / (q^2 - s)`` if ``q^2 > s``, else
``inf`` (their Eq. 20).

Training (Tipping & Faul 2003, Sec. 4, with the shared alpha). Start from the empty model (or, with
``fit(start=...)``, from another fit's relevance vectors, precisions and noise: ``MVRVM._warm_start``). Each
iteration finds the move with the largest gain in ``L``: add an inactive basis function at its optimal
alpha, re-estimate an active one, or delete one (never the last). Active basis functions are ranked by
deletion and by two Newton steps towards their nearest optimum, and the best-ranked re-estimate then
goes to its global optimum; inactive ones go through branch and bound with two cheap upper bounds on
``max l`` (``_series_bound``, ``_mode_bounds``), so only the few whose bound beats the best gain so far
are solved exactly. Moves update ``mu_p``, ``S``, ``Q`` and the covariances of every output by the
rank-one formulas of Tipping & Faul's appendix. Termination (SparseBayes's rule) is proposed when no move
raises ``L``, or when the best move is a re-estimate changing ``log alpha`` by less than ``tol`` and no
addition or deletion would raise ``L`` (all candidates then solved exactly); it stands when the noise
re-estimate changes no ``log beta_p`` by ``tol_beta`` or more. ``max_iter`` bounds the iterations.

Noise: per output, Tipping's re-estimate ``beta_p = (N - gamma_p) / ||y_p - Phi mu_p||^2`` with
``gamma_p = sum_m (1 - alpha_m Sigma_p,mm)``, capped at ``beta_max / v_p`` (``v_p`` the variance of output
p: near-noise-free targets would otherwise drive ``beta_p`` to infinity; SparseBayes's BetaMaxFactor). It
is a fixed-point step and can overshoot, so the EM step ``N / (||y_p - Phi mu_p||^2 + gamma_p / beta_p)``
is evaluated too and the value (old, re-estimate or EM) with the largest ``L_p`` is kept: ``L`` never
decreases. The noise is re-estimated after each of the first 10 iterations, at termination proposals,
and otherwise when the re-estimate would change some ``log beta_p`` by more than ``tol``, checked every
``max(beta_update_every, k / P)`` iterations (``k`` active basis functions): a re-estimate needs a full
recomputation, which costs about as much as ``k / P`` moves.

Numerics: because ``alpha`` is shared, one symmetric eigendecomposition
``A^-1/2 Phi'Phi A^-1/2 = V diag(d) V'`` gives the posterior of every output and every ``beta``:
``Sigma_p = W diag(1 / (1 + beta_p d)) W'`` with ``W = A^-1/2 V``, ``log|C_p| = -N log beta_p + sum log(1 +
beta_p d)``; ``I + beta_p diag(d)`` has eigenvalues >= 1, so nothing can fail to factorise, no jitter is
needed and nothing is inverted explicitly. Between full recomputations the covariances are this
factorisation plus the moves' rank-one terms (``_Posterior``). A candidate almost collinear with an active
basis function (cosine above ``alignment_max``) is not added, as in SparseBayes, whose control settings
(initial noise at 10 % of the target standard deviation, MinDeltaLogAlpha, MinDeltaLogBeta,
BetaMaxFactor, AlignmentMax, 10 initial noise updates) are the defaults here.
"""

import logging

import numpy as np
import pandas as pd

from voxpose.errors import VoxposeError
from voxpose.regression.kernels import check_width, design_matrix, holdout_split, median_pairwise_distance
from voxpose.validation import as_rows

log = logging.getLogger(__name__)

_LOG_2PI = float(np.log(2.0 * np.pi))
_SNR_INIT = 100.0  # initial beta_p * v_p: noise standard deviation 10 % of the target's (SparseBayes)
_MIN_GAIN = 1e-8  # a move must raise log L by more than this (nats): smaller is round-off
_IMAG_TOL = 1e-6  # a root is real when |imag| <= _IMAG_TOL * |root|
_BATCH = 32  # basis functions solved exactly per batch in the branch and bound
_RANK_NEWTON = 2  # Newton steps ranking the active basis functions' re-estimates
_POLISH = 1  # Newton steps polishing the roots of the stationarity polynomial
_BETA_UPDATE_START = 10  # noise re-estimated after each of the first iterations (SparseBayes)
_MIN_CORRECTIONS = 32  # rank-one covariance terms allowed before a recomputation, at least


def _contribution(alpha, s, q2) -> np.ndarray:
    """``l(alpha)``: summed over the last axis of ``s`` and ``q2`` (..., P); ``alpha`` (...,) may be inf."""
    a = np.asarray(alpha, dtype=np.float64)[..., None]
    return 0.5 * np.sum(q2 / (a + s) - np.log1p(s / a), axis=-1)


def _mode_bounds(s, q2) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cheap lower and upper bounds on ``max l`` for many basis functions at once; s, q2 (n, P).

    Each output's term ``l_p`` is unimodal in ``log alpha`` (it rises to its maximum at the single-output
    optimum ``s^2 / (q^2 - s)`` when ``q^2 > s``, else rises towards 0 at infinity). Evaluating ``l`` at
    these P modes gives feasible values (lower bounds); between two consecutive modes every ``l_p`` is
    monotone, so its maximum there is at one end, which bounds ``l`` on that interval from above.

    Returns
    -------
    best_value : (n,) largest ``l`` at a finite mode (-inf when there is none).
    best_alpha : (n,) that mode (inf when there is none).
    upper : (n,) upper bound on ``l`` over (0, inf].
    """
    n, p = s.shape
    wants = q2 > s
    with np.errstate(divide="ignore"):
        mode = np.where(wants, s * s / np.where(wants, q2 - s, 1.0), np.inf)
    order = np.argsort(mode, axis=1)
    ss, qs = np.take_along_axis(s, order, 1), np.take_along_axis(q2, order, 1)
    points = np.concatenate([np.take_along_axis(mode, order, 1), np.full((n, 1), np.inf)], axis=1)
    a = points[:, :, None]
    terms = 0.5 * (qs[:, None, :] / (a + ss[:, None, :]) - np.log1p(ss[:, None, :] / a))  # (n, P+1, P)
    total = terms.sum(axis=2)
    partial = np.cumsum(terms, axis=2)
    i = np.arange(p)
    # on [point_i, point_i+1]: sorted outputs r <= i decrease (max at the left end), r > i increase
    upper = np.max(partial[:, i, i] + total[:, i + 1] - partial[:, i + 1, i], axis=1)
    finite_total = np.where(np.isfinite(points[:, :p]), total[:, :p], -np.inf)
    best = np.argmax(finite_total, axis=1)
    rows = np.arange(n)
    return finite_total[rows, best], points[rows, best], upper


def _series_bound(s, q2) -> np.ndarray:
    """A second upper bound on ``max l`` (n,), tight for weakly relevant basis functions; s, q2 (n, P).

    With ``v_p = s_p / (alpha + s_p)`` in (0, 1), ``l = 1/2 sum_p [theta_p v_p + log(1 - v_p)]``,
    ``theta_p = q_p^2 / s_p``, and ``log(1 - v) <= -v - v^2 / 2``. All ``v_p`` lie between ``v`` (of the
    smallest s) and ``rho v / (1 + (rho - 1) v)`` (of the largest, ``rho = max s / min s``), so

        2 l <= g(v) = A rho v / (1 + (rho - 1) v) - C v - P v^2 / 2,
        A = sum_{theta > 1} (theta - 1),  C = sum_{theta <= 1} (1 - theta),

    a concave function of ``v`` in (0, 1). Newton steps from ``v = 0`` approach its maximiser from below
    (``g'`` is convex and decreasing), and the tangent at the last point bounds ``g`` from above.
    """
    p = s.shape[1]
    theta = q2 / s
    big_a = np.sum(np.maximum(theta - 1.0, 0.0), axis=1)
    big_c = np.sum(np.maximum(1.0 - theta, 0.0), axis=1)
    rho = np.max(s, axis=1) / np.min(s, axis=1)

    def slope(v):
        den = 1.0 + (rho - 1.0) * v
        return big_a * rho / den**2 - big_c - p * v, -2.0 * big_a * rho * (rho - 1.0) / den**3 - p

    v = np.zeros_like(rho)
    for _ in range(6):
        d1, d2 = slope(v)
        v = np.clip(v - np.where(d1 > 0, d1 / d2, 0.0), 0.0, 1.0)
    d1, _ = slope(v)
    g = big_a * rho * v / (1.0 + (rho - 1.0) * v) - big_c * v - 0.5 * p * v * v
    return 0.5 * np.maximum(g + np.where(d1 > 0, d1 * (1.0 - v), -d1 * v), 0.0)


def _slope_terms(alpha, s, q2):
    """``g = sum_p h_p`` (``dl/dlog(alpha) = g / 2``) and ``dg/dlog(alpha)``; alpha (...,), s and q2 (..., P)."""
    a = np.asarray(alpha)[..., None]
    apc = a + s
    g = np.sum((s * s + a * (s - q2)) / apc**2, axis=-1)
    dg = alpha * np.sum(((s - q2) * (s - a) - 2.0 * s * s) / apc**3, axis=-1)
    return g, dg


def _newton_ascent(alpha, s, q2, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Up to ``steps`` uphill steps of ``l`` from ``alpha`` (n,), for rows of ``s``, ``q2`` (n, P).

    Safeguarded Newton steps in ``log alpha`` (where ``l`` is concave; elsewhere a step of 8 uphill),
    halved until ``l`` rises; a row stops early when no step raises ``l`` or the step is below 1e-7 (a
    local maximum). Beyond ``alpha = 1e3 max_p max(s_p, q_p^2)``, ``l`` is ``sum_p (q_p^2 - s_p) / (2 alpha)``
    to 0.1 %, monotone, so a row climbing there goes on to ``alpha = inf``. Returns the point reached
    (inf allowed) and ``l`` there, never below ``l`` at the start.
    """
    t = np.log(alpha)
    top = np.log(np.max(np.maximum(s, q2), axis=1)) + np.log(1e3)
    value = _contribution(alpha, s, q2)
    gone = np.zeros(t.size, dtype=bool)
    halvings = 0.5 ** np.arange(1, 10)
    moving = np.arange(t.size)
    for _ in range(steps):
        if not moving.size:
            break
        tm, sm, qm = t[moving], s[moving], q2[moving]
        g, dg = _slope_terms(np.exp(tm), sm, qm)
        leaving = (tm >= top[moving]) & (g > 0)
        gone[moving[leaving]] = True
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.clip(np.where(dg < 0, -g / dg, 8.0 * np.sign(g)), -8.0, 8.0)
        new_t = tm + step
        new_value = _contribution(np.exp(new_t), sm, qm)
        failed = np.flatnonzero(~(new_value > value[moving]))
        if failed.size:  # backtrack: the first halving that raises l
            trial = tm[failed, None] + step[failed, None] * halvings
            trial_value = _contribution(np.exp(trial), sm[failed, None, :], qm[failed, None, :])
            better = trial_value > value[moving[failed], None]
            first = np.argmax(better, axis=1)
            rows = np.arange(failed.size)
            ok = better[rows, first]
            new_t[failed] = np.where(ok, trial[rows, first], tm[failed])
            new_value[failed] = np.where(ok, trial_value[rows, first], value[moving[failed]])
            step[failed] = np.where(ok, step[failed] * halvings[first], 0.0)
        moved = (step != 0.0) & ~leaving
        t[moving[moved]] = new_t[moved]
        value[moving[moved]] = new_value[moved]
        moving = moving[moved & (np.abs(step) > 1e-7)]
    return np.where(gone, np.inf, np.exp(t)), np.where(gone, 0.0, value)


def _numerator(st: np.ndarray, qt: np.ndarray) -> np.ndarray:
    """Coefficients (n, 2P), lowest power first, of ``sum_p [st_p^2 + u (st_p - qt_p)] prod_{r != p} (u + st_r)^2``.

    Products of all squares before and after each output (prefix and suffix), then their pairwise
    products for all outputs at once; rows are basis functions.
    """
    n, p = st.shape
    length = 2 * p - 1
    prefix, suffix = np.zeros((n, p, length)), np.zeros((n, p, length))

    def times_square(c, v):  # c * (u + v)^2, lowest power first
        out = (v * v)[:, None] * c
        out[:, 1:] += 2.0 * v[:, None] * c[:, :-1]
        out[:, 2:] += c[:, :-2]
        return out

    c = np.zeros((n, length))
    c[:, 0] = 1.0
    for r in range(p):
        prefix[:, r] = c
        c = times_square(c, st[:, r])
    c = np.zeros((n, length))
    c[:, 0] = 1.0
    for r in reversed(range(p)):
        suffix[:, r] = c
        c = times_square(c, st[:, r])
    others = np.zeros((n, p, length))
    for k in range(length):
        others[:, :, k:] += prefix[:, :, k : k + 1] * suffix[:, :, : length - k]
    poly = np.zeros((n, 2 * p))
    poly[:, :-1] = np.einsum("np,npk->nk", st * st, others)
    poly[:, 1:] += np.einsum("np,npk->nk", st - qt, others)
    return poly


def _stationary_points(s, q2) -> np.ndarray:
    """Stationary points of ``l`` for rows of ``s``, ``q2`` (n, P), P >= 2: (n, 2P - 1), NaN where none.

    The real positive roots in alpha of ``sum_p [s_p^2 + alpha (s_p - q2_p)] prod_{r != p} (alpha + s_r)^2``,
    found as eigenvalues of the companion matrices of the polynomial in ``u = alpha / c`` (``c`` the
    geometric mean of the row's ``s``), then polished by ``_POLISH`` Newton steps in ``log alpha`` (each kept only if it
    shrinks the slope).
    """
    n, p = s.shape
    scale = np.exp(np.mean(np.log(s), axis=1))
    poly = _numerator(s / scale[:, None], q2 / scale[:, None])[:, ::-1]  # highest power first
    poly = poly / np.max(np.abs(poly), axis=1, keepdims=True)
    # a vanishing leading coefficient is a root at infinity, where l is 0 anyway: keep the degree fixed
    lead = poly[:, 0]
    poly[:, 0] = np.where(np.abs(lead) < 1e-14, np.where(lead < 0, -1e-14, 1e-14), lead)
    companion = np.zeros((n, 2 * p - 1, 2 * p - 1))
    companion[:, 0, :] = -poly[:, 1:] / poly[:, :1]
    companion[:, np.arange(1, 2 * p - 1), np.arange(2 * p - 2)] = 1.0
    roots = np.linalg.eigvals(companion)
    real = (roots.real > 0) & (np.abs(roots.imag) <= _IMAG_TOL * np.abs(roots))
    t = np.log(np.where(real, roots.real, np.nan) * scale[:, None])
    ss, qq = s[:, None, :], q2[:, None, :]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for _ in range(_POLISH):
            g, dg = _slope_terms(np.exp(t), ss, qq)
            step = np.where(dg != 0.0, g / dg, 0.0)
            g_new, _ = _slope_terms(np.exp(t - step), ss, qq)
            t = np.where(np.abs(g_new) < np.abs(g), t - step, t)
    return np.exp(t)


def optimal_alpha(s, q2) -> tuple[np.ndarray, np.ndarray]:
    """The shared precision maximising ``l(alpha)``, and ``l`` there, for each of n basis functions.

    Parameters
    ----------
    s : (n, P) sparsity factors ``s_mp`` (positive).
    q2 : (n, P) squared quality factors ``q_mp^2``.

    Returns
    -------
    alpha : (n,) maximisers in (0, inf]; ``inf`` means the basis function is better left out.
    value : (n,) ``l(alpha)`` (0 at ``alpha = inf``): log marginal likelihood relative to leaving it out.
    """
    s = np.asarray(s, dtype=np.float64)
    q2 = np.asarray(q2, dtype=np.float64)
    wants = q2 > s
    with np.errstate(divide="ignore", invalid="ignore"):
        single = np.where(wants, s * s / (q2 - s), np.nan)  # each output's own optimum
    candidates = np.concatenate([single, _stationary_points(s, q2)], axis=1) if s.shape[1] > 1 else single
    with np.errstate(invalid="ignore"):
        values = _contribution(candidates, s[:, None, :], q2[:, None, :])
    values = np.where(np.isnan(candidates), -np.inf, values)
    best = np.argmax(values, axis=1)
    rows = np.arange(s.shape[0])
    alpha, value = candidates[rows, best], values[rows, best]
    # no finite candidate beats leaving the basis function out (l = 0 at infinity)
    out = ~(value > 0.0)
    return np.where(out, np.inf, alpha), np.where(out, 0.0, value)


class _Posterior:
    """Posterior over the active basis functions of all P outputs, with S and Q of the basis functions.

    S and Q are kept for the *tracked* basis functions (``rows``): the active ones and those not excluded
    by the alignment test; an excluded one is never a candidate, so its factors are recomputed only when
    the exclusion ends (its aligned partner deleted), which spares most of the per-move work when many
    training rows are near duplicates.

    Basis functions sit in slots (``slot_basis``); a deleted one leaves a dead slot until the next
    ``refresh`` compacts them. ``cross[:, i] = Phi' phi`` of slot i (B,), ``mu`` (P, slots). The covariances
    are kept implicitly, since P explicit (k, k) matrices would make every move cost P k^2 memory traffic:

        Sigma_p = W diag(c_p) W' (padded with zeros to all slots)  +  sum_r weight_pr u_pr u_pr',

    the first term from the eigendecomposition of the last ``refresh`` (shared by all outputs), the
    second the rank-one terms of the moves since (``u`` (P, r, slots), ``weight`` (P, r)).
    """

    def __init__(self, phi: np.ndarray, y: np.ndarray, beta: np.ndarray, alignment_max: float):
        self.phi, self.y, self.beta = phi, y, beta.copy()
        self.n, self.n_basis = phi.shape
        self.p = y.shape[1]
        self.norms2 = np.einsum("nb,nb->b", phi, phi)
        self.phity = phi.T @ y
        self.yy = np.sum(y * y, axis=0)
        self.alignment_max = alignment_max
        self.alpha = np.full(self.n_basis, np.inf)
        self.n_aligned = np.zeros(self.n_basis, dtype=np.int64)
        self.n_slots = self.n_corrections = 0
        self.slot_basis = np.empty(0, dtype=np.int64)
        self.live = np.empty(0, dtype=bool)
        self.cross = np.empty((self.n_basis, 0))
        self.mu = np.empty((self.p, 0))
        self.diag = np.empty((self.p, 0))  # diagonal of every Sigma_p over the slots
        self.u = np.empty((self.p, 0, 0))
        self.weight = np.empty((self.p, 0))
        self.w = np.empty((0, 0))
        self.c = np.empty((0, self.p))
        self.tracked = np.ones(self.n_basis, dtype=bool)
        self.rows = np.arange(self.n_basis)

    @property
    def active_basis(self) -> np.ndarray:
        return self.slot_basis[: self.n_slots][self.live[: self.n_slots]]

    @property
    def k(self) -> int:
        return int(np.count_nonzero(self.live[: self.n_slots]))

    def _reserve(self) -> None:
        """Room for one more slot and one more correction (capacities double)."""
        ns, r = self.n_slots, self.n_corrections
        if ns == self.slot_basis.size:
            cap = max(16, 2 * ns)
            self.slot_basis = np.resize(self.slot_basis, cap)
            self.live = np.concatenate([self.live[:ns], np.zeros(cap - ns, dtype=bool)])
            cross = np.empty((self.n_basis, cap))
            cross[:, :ns] = self.cross[:, :ns]
            self.cross = cross
            self.mu = np.concatenate([self.mu[:, :ns], np.zeros((self.p, cap - ns))], axis=1)
            self.diag = np.concatenate([self.diag[:, :ns], np.zeros((self.p, cap - ns))], axis=1)
            u = np.zeros((self.p, self.u.shape[1], cap))
            u[:, :r, :ns] = self.u[:, :r, :ns]
            self.u = u
        if r == self.u.shape[1]:
            cap = max(16, 2 * r)
            u = np.zeros((self.p, cap, self.u.shape[2]))
            u[:, :r] = self.u[:, :r]
            self.u = u
            self.weight = np.concatenate([self.weight[:, :r], np.zeros((self.p, cap - r))], axis=1)

    def _correct(self, vectors: np.ndarray, weights: np.ndarray) -> None:
        """Add the rank-one terms ``weights[p] * v_p v_p'`` (vectors (P, n_slots)) to every Sigma_p."""
        r = self.n_corrections
        self.u[:, r, : vectors.shape[1]] = vectors
        self.weight[:, r] = weights
        self.diag[:, : vectors.shape[1]] += weights[:, None] * vectors * vectors
        self.n_corrections = r + 1

    def _sigma_times(self, v: np.ndarray) -> np.ndarray:
        """``Sigma_p v`` for all outputs; v (n_slots,) -> (P, n_slots)."""
        k0, ns, r = self.w.shape[0], self.n_slots, self.n_corrections
        return self._combine(v[:k0] @ self.w, self.u[:, :r, :ns] @ v if r else None)

    def _sigma_column(self, i: int) -> np.ndarray:
        """Column ``i`` of every Sigma_p, (P, n_slots)."""
        k0, r = self.w.shape[0], self.n_corrections
        return self._combine(self.w[i] if i < k0 else np.zeros(k0), self.u[:, :r, i] if r else None)

    def _combine(self, projected: np.ndarray, along: np.ndarray | None) -> np.ndarray:
        """``Sigma_p v`` from ``W' v`` (k0,) and the rank-one terms' ``u_pr' v`` (P, r)."""
        k0, ns, r = self.w.shape[0], self.n_slots, self.n_corrections
        out = np.zeros((self.p, ns))
        out[:, :k0] = (projected * self.c.T) @ self.w.T
        if r:
            out += np.matmul((along * self.weight[:, :r])[:, None, :], self.u[:, :r, :ns])[:, 0, :]
        return out

    def factors(self) -> tuple[np.ndarray, np.ndarray]:
        """``s`` and ``q`` (B, P) of every basis function (active ones exclude their own contribution).

        For an active basis function, ``Sigma_jj = 1 / (alpha + s)`` and ``mu_j = Sigma_jj q``, so
        ``q = mu_j / Sigma_jj`` and ``s = 1 / Sigma_jj - alpha``, which loses digits only when ``s << alpha``;
        there ``s = alpha S / (alpha - S)`` is accurate instead (it loses them when ``s >> alpha``).
        """
        s, q = self.S.copy(), self.Q.copy()
        slots = np.flatnonzero(self.live[: self.n_slots])
        act = self.slot_basis[slots]
        a = self.alpha[act][:, None]
        diag = self.diag[:, slots].T
        with np.errstate(divide="ignore", invalid="ignore"):
            from_diag = 1.0 / diag - a
            s[act] = np.where(from_diag > a, from_diag, a * self.S[act] / (a - self.S[act]))
            q[act] = self.mu[:, slots].T / diag
        return s, q

    def _aligned(self, column: np.ndarray, j: int) -> np.ndarray:
        """Basis functions whose cosine with basis function ``j`` (its ``cross`` column) exceeds the limit."""
        with np.errstate(divide="ignore", invalid="ignore"):
            cosine = column / np.sqrt(self.norms2 * self.norms2[j])
        return cosine > self.alignment_max

    def add(self, j: int, alpha: float) -> None:
        """Make basis function ``j`` active with precision ``alpha`` (Tipping & Faul, Appendix A.2)."""
        self._reserve()
        ns = self.n_slots
        column = self.phi.T @ self.phi[:, j]
        g = np.where(self.live[:ns], column[self.slot_basis[:ns]], 0.0)
        sv = self.beta[:, None] * self._sigma_times(g)  # (P, ns)
        sig_jj = 1.0 / (alpha + self.S[j])  # (P,)
        mu_j = sig_jj * self.Q[j]
        rows = self.rows
        e = self.beta * (column[rows, None] - self.cross[rows, :ns] @ sv.T)  # (tracked, P)
        self.S[rows] -= sig_jj * e * e
        self.Q[rows] -= mu_j * e
        self.mu[:, :ns] -= mu_j[:, None] * sv
        self.mu[:, ns] = mu_j
        self._correct(np.concatenate([sv, -np.ones((self.p, 1))], axis=1), sig_jj)
        self.cross[:, ns] = column
        self.slot_basis[ns] = j
        self.live[ns] = True
        self.n_slots = ns + 1
        self.alpha[j] = alpha
        self.n_aligned += self._aligned(column, j)
        self._track()

    def _track(self) -> None:
        """Update the tracked basis functions; recompute S and Q of those whose exclusion just ended."""
        tracked = np.isfinite(self.alpha) | (self.n_aligned == 0)
        self.S[~tracked] = self.Q[~tracked] = np.nan
        for m in np.flatnonzero(tracked & ~self.tracked):
            ns = self.n_slots
            g = np.where(self.live[:ns], self.cross[m, :ns], 0.0)
            sigma_g = self._sigma_times(g)
            self.S[m] = self.beta * self.norms2[m] - self.beta**2 * (sigma_g @ g)
            self.Q[m] = self.beta * (self.phity[m] - self.mu[:, :ns] @ g)
        self.tracked = tracked
        self.rows = np.flatnonzero(tracked)

    def _downdate(self, i: int, col: np.ndarray, kappa: np.ndarray) -> None:
        """Shared part of re-estimation (Tipping & Faul, Appendix A.3) and deletion (A.4) of slot ``i``."""
        self._reserve()
        ns = self.n_slots
        mu_i = self.mu[:, i].copy()
        self.mu[:, :ns] -= (kappa * mu_i)[:, None] * col
        rows = self.rows
        t = self.beta * (self.cross[rows, :ns] @ col.T)  # (tracked, P)
        self.S[rows] += kappa * t * t
        self.Q[rows] += kappa * mu_i * t
        self._correct(col, -kappa)

    def slot(self, j: int) -> int:
        return int(np.flatnonzero(self.live[: self.n_slots] & (self.slot_basis[: self.n_slots] == j))[0])

    def reestimate(self, j: int, alpha: float) -> None:
        """Change the precision of active basis function ``j`` to the finite ``alpha``."""
        i = self.slot(j)
        col = self._sigma_column(i)
        self._downdate(i, col, 1.0 / (col[:, i] + 1.0 / (alpha - self.alpha[j])))
        self.alpha[j] = alpha

    def delete(self, j: int) -> None:
        """Remove active basis function ``j`` (its precision goes to infinity); its slot dies."""
        i = self.slot(j)
        col = self._sigma_column(i)
        self._downdate(i, col, 1.0 / col[:, i])
        self.mu[:, i] = 0.0
        self.live[i] = False
        self.alpha[j] = np.inf
        self.n_aligned -= self._aligned(self.cross[:, i], j)
        self._track()

    def noise_change(self, beta_cap: np.ndarray) -> float:
        """Largest ``|change of log beta_p|`` the noise re-estimate would make now (no state change).

        Cheap: ``Phi' (y_p - Phi mu_p) = Q_p / beta_p`` for every basis function, so the squared residual is
        ``||y_p||^2 - sum_j mu_jp (phi_j' y_p + Q_jp / beta_p)`` over the active ones.
        """
        slots = np.flatnonzero(self.live[: self.n_slots])
        act = self.slot_basis[slots]
        mu = self.mu[:, slots].T  # (k, P)
        resid2 = self.yy - np.sum(mu * (self.phity[act] + self.Q[act] / self.beta), axis=0)
        gamma = slots.size - np.sum(self.alpha[act][:, None] * self.diag[:, slots].T, axis=0)
        with np.errstate(divide="ignore"):
            proposal = np.minimum((self.n - gamma) / np.maximum(resid2, 0.0), beta_cap)
        return float(np.max(np.abs(np.log(proposal / self.beta))))

    def refresh(self, update_beta: bool, beta_cap: np.ndarray) -> tuple[float, float]:
        """Recompute the posterior, S and Q from scratch, first re-estimating beta if asked.

        Dead slots are dropped and the rank-one terms folded into a new eigendecomposition. Returns the
        log marginal likelihood and the largest ``|change of log beta_p|``.
        """
        keep = np.flatnonzero(self.live[: self.n_slots])
        act = self.slot_basis[keep]
        k = act.size
        cross = self.cross[:, keep]
        self.cross[:, :k] = cross
        self.slot_basis[:k] = act
        self.live[:] = False
        self.live[:k] = True
        self.u[:, : self.n_corrections, : self.n_slots] = 0.0  # rows are reused by later corrections
        self.n_slots, self.n_corrections = k, 0
        inv_sqrt_alpha = 1.0 / np.sqrt(self.alpha[act])
        gram = cross[act]
        whitened = inv_sqrt_alpha[:, None] * (0.5 * (gram + gram.T)) * inv_sqrt_alpha[None, :]
        d, v = np.linalg.eigh(whitened)
        d = np.maximum(d, 0.0)
        w = inv_sqrt_alpha[:, None] * v  # Sigma_p = w diag(1 / (1 + beta_p d)) w'
        z = w.T @ self.phity[act]  # (k, P)
        phi_act = self.phi[:, act]

        def evaluate(beta):
            shrink = 1.0 / (1.0 + beta[None, :] * d[:, None])  # (k, P)
            mu = w @ (beta * shrink * z)
            resid2 = np.sum((self.y - phi_act @ mu) ** 2, axis=0)
            logdet = np.sum(np.log1p(beta[None, :] * d[:, None]), axis=0) - self.n * np.log(beta)
            quad = beta * resid2 + np.sum(self.alpha[act][:, None] * mu * mu, axis=0)
            return -0.5 * (self.n * _LOG_2PI + logdet + quad), shrink, mu, resid2

        lml, shrink, mu, resid2 = evaluate(self.beta)
        old = self.beta
        if update_beta:
            gamma = k - shrink.sum(axis=0)
            with np.errstate(divide="ignore"):  # a perfect fit: both go to the cap
                mackay = (self.n - gamma) / resid2
                em = self.n / (resid2 + gamma / self.beta)
            options = [self.beta] + [np.minimum(b, beta_cap) for b in (mackay, em)]
            values = [lml] + [evaluate(b)[0] for b in options[1:]]
            pick = np.argmax(np.stack(values), axis=0)
            self.beta = np.choose(pick, options)
            lml, shrink, mu, resid2 = evaluate(self.beta)
        self.w, self.c = w, shrink
        self.mu[:] = 0.0
        self.mu[:, :k] = mu.T
        self.diag[:] = 0.0
        self.diag[:, :k] = ((w * w) @ shrink).T
        rows = self.rows
        f = cross[rows] @ w  # (tracked, k)
        beta = self.beta
        self.S, self.Q = np.full((self.n_basis, self.p), np.nan), np.full((self.n_basis, self.p), np.nan)
        self.S[rows] = beta * self.norms2[rows, None] - beta**2 * ((f * f) @ shrink)
        self.Q[rows] = beta * self.phity[rows] - beta**2 * (f @ (shrink * z))
        return float(lml.sum()), float(np.max(np.abs(np.log(self.beta / old))))


class MVRVM:
    """Multi-Variate Relevance Vector Machine regression (Section 3; Thayananthan et al. 2006).

    Parameters
    ----------
    kernel : ``"rbf"``, the Gaussian kernel of ``voxpose.regression.kernels`` (the only kernel the paper uses).
    kernel_width : width ``w`` of ``exp(-||x - x'||^2 / (2 w^2))``, or ``"median"``: the median pairwise
        distance of the training rows.
    bias : include the constant basis function of Eq. 3.
    max_iter : maximum number of iterations (one move or noise update each).
    tol : termination threshold on the change of ``log alpha`` of the best re-estimate (SparseBayes's
        MinDeltaLogAlpha).
    tol_beta : termination threshold on changes of ``log beta_p`` (SparseBayes's MinDeltaLogBeta).
    beta_max : cap on ``beta_p`` times the variance of output p (a signal-to-noise ratio).
    beta_update_every : after the first 10 iterations (which all re-estimate the noise), the fewest
        iterations between checks of the noise re-estimate; checks are ``max(beta_update_every, k / P)``
        iterations apart for ``k`` active basis functions.
    alignment_max : cosine above which a candidate counts as collinear with an active basis function.
    random_state : seed for the row subset of the median distance when there are more than 2000 rows.

    Attributes
    ----------
    relevance_ : (R,) indices of the training rows whose Gaussians were kept, increasing.
    relevance_vectors_ : (R, d) those training rows.
    has_bias_ : whether the bias basis function was kept.
    coef_ : (has_bias_ + R, P) posterior mean weights: bias row first when kept, then ``relevance_`` order.
    alpha_ : (has_bias_ + R,) weight precisions, same order.
    sigma_ : (P, has_bias_ + R, has_bias_ + R) posterior weight covariance per output.
    beta_ : (P,) noise precisions; ``1 / sqrt(beta_)`` is the noise standard deviation per output.
    kernel_width_ : the width used.
    log_marginal_likelihood_ : (n_iter_ + 1,) log marginal likelihood, initially and after each iteration.
    n_iter_ : iterations run.
    converged_ : whether the convergence criterion was met before ``max_iter``.
    """

    def __init__(
        self,
        kernel: str = "rbf",
        kernel_width="median",
        bias: bool = True,
        max_iter: int = 10000,
        tol: float = 1e-3,
        tol_beta: float = 1e-6,
        beta_max: float = 1e6,
        beta_update_every: int = 10,
        alignment_max: float = 0.999,
        random_state=None,
    ):
        self.kernel = kernel
        self.kernel_width = kernel_width
        self.bias = bias
        self.max_iter = max_iter
        self.tol = tol
        self.tol_beta = tol_beta
        self.beta_max = beta_max
        self.beta_update_every = beta_update_every
        self.alignment_max = alignment_max
        self.random_state = random_state

    def _check_params(self) -> None:
        if self.kernel != "rbf":
            raise VoxposeError(f"MVRVM: unknown kernel {self.kernel!r}; the only kernel is 'rbf'")
        if self.kernel_width != "median":
            check_width(self.kernel_width)
        for name in ("max_iter", "beta_update_every"):
            value = getattr(self, name)
            if not isinstance(value, int | np.integer) or value < 1:
                raise VoxposeError(f"MVRVM: {name} must be a positive integer, got {value!r}")
        for name, top in (("tol", np.inf), ("tol_beta", np.inf), ("beta_max", np.inf), ("alignment_max", 1.0)):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and 0 < value <= top and np.isfinite(value)):
                raise VoxposeError(f"MVRVM: {name} must be a number in (0, {top}], got {value!r}")

    def fit(self, X, Y, start=None) -> "MVRVM":
        """Learn the sparse mapping from features ``X`` (N, d) to targets ``Y`` (N, P) or (N,); returns self.

        ``start``: ``(model, rows)``, an MVRVM of the same kernel width fitted on the rows ``rows`` of ``X``
        (e.g. the candidate of ``select_kernel_width``). Training then starts from its relevance vectors,
        precisions and noise instead of the empty model (``_warm_start``).
        """
        self._check_params()
        x = as_rows(X, "MVRVM: X")
        y_arr = np.asarray(Y, dtype=np.float64)
        self._single_output = y_arr.ndim == 1
        y = as_rows(y_arr[:, None] if self._single_output else y_arr, "MVRVM: Y")
        if y.shape[0] != x.shape[0]:
            raise VoxposeError(f"MVRVM: X has {x.shape[0]} rows but Y has {y.shape[0]}")
        if x.shape[0] < 2:
            raise VoxposeError(f"MVRVM: needs at least 2 training rows, got {x.shape[0]}")
        if self.kernel_width == "median":
            self.kernel_width_ = median_pairwise_distance(x, random_state=self.random_state)
        else:
            self.kernel_width_ = check_width(self.kernel_width)
        phi = design_matrix(x, x, self.kernel_width_, self.bias)
        var = y.var(axis=0)
        scale = np.where(var > 0, var, np.where(np.mean(y * y, axis=0) > 0, np.mean(y * y, axis=0), 1.0))
        cap = self.beta_max / scale
        post = _Posterior(phi, y, np.minimum(_SNR_INIT / scale, cap), self.alignment_max)
        lml, _ = post.refresh(update_beta=False, beta_cap=cap)
        if start is not None:
            lml = self._warm_start(post, *start, cap)
        trace = [lml]
        self.converged_ = False
        next_check = _BETA_UPDATE_START  # next iteration at which the noise re-estimate is considered
        for it in range(1, self.max_iter + 1):
            move = self._best_move(post, exhaustive=False)
            if self._settled(move, post):
                move = self._best_move(post, exhaustive=True)
            if self._settled(move, post):
                # termination proposed: it stands unless the noise re-estimate changes beta
                if post.noise_change(cap) < self.tol_beta:
                    self.converged_ = True
                else:
                    lml, change = post.refresh(update_beta=True, beta_cap=cap)
                    self.converged_ = change < self.tol_beta
            else:
                j, alpha, gain = move
                if not np.isfinite(post.alpha[j]):
                    post.add(j, alpha)
                elif np.isfinite(alpha):
                    post.reestimate(j, alpha)
                else:
                    post.delete(j)
                lml += gain
                if (
                    it <= _BETA_UPDATE_START
                    or post.n_corrections > max(_MIN_CORRECTIONS, post.n_slots)
                    or (it >= next_check and post.noise_change(cap) > self.tol)
                ):
                    lml, _ = post.refresh(update_beta=True, beta_cap=cap)
                if it >= next_check:
                    next_check = it + max(self.beta_update_every, post.n_slots // post.p)
            trace.append(lml)
            if it % 200 == 0:
                log.info("MVRVM iteration %d: %d basis functions, log ML %.6g", it, post.k, lml)
            if self.converged_:
                break
        if not self.converged_:
            log.warning("MVRVM: no convergence in %d iterations (tol %g)", self.max_iter, self.tol)
        post.refresh(update_beta=False, beta_cap=cap)  # fold the rank-one terms into the final posterior
        self.n_iter_ = it
        self.log_marginal_likelihood_ = np.array(trace)
        self._store(post, x)
        log.info(
            "MVRVM: %s after %d iterations, %d of %d basis functions kept, log ML %.6g",
            "converged" if self.converged_ else "stopped",
            it,
            post.k,
            post.n_basis,
            lml,
        )
        return self

    def _warm_start(self, post: _Posterior, model: "MVRVM", rows, cap: np.ndarray) -> float:
        """Activate ``model``'s basis functions (rows ``rows[model.relevance_]`` of this fit, and the bias if it
        kept one) at its precisions, with its noise; returns the log marginal likelihood.

        Why: from the empty model the first moves can stall. With one weak basis function active, the noise
        re-estimate of the first iterations absorbs the whole target variance, and then no single Gaussian
        raises the likelihood. A candidate fitted on most of the same rows is a nearby point of the same
        likelihood. Measured on the default run (fixed width, 2000 moves, cold start against this one):
        Figure 4's 600-d concatenated 2D shape contexts at width 0.41, the cold fit stopped after 5 moves
        with the bias alone (log ML -12967, the mean pose's 10.14 deg), the warm one kept 156 relevance
        vectors (-10390, 7.54 deg); where the cold fit does not stall it ends a little higher and the test
        error is the same (Table 1 MPPCA: -37586 cold, -37681 warm, 4.18 and 4.11 deg; Table 1 concatenated
        2D shape contexts: -33531, -33703, 3.62 and 3.63 deg), in the same time.
        """
        if model.kernel_width_ != self.kernel_width_ or model.coef_.shape[1] != post.p:
            raise VoxposeError("MVRVM: a warm start needs a model of the same kernel width and outputs")
        basis = np.asarray(rows)[model.relevance_] + int(self.bias)
        if model.has_bias_:
            basis = np.concatenate([[0], basis]) if self.bias else basis
        post.beta = np.minimum(model.beta_, cap)
        post.refresh(update_beta=False, beta_cap=cap)
        for j, alpha in zip(basis, model.alpha_[len(model.alpha_) - len(basis) :], strict=True):
            if np.isfinite(post.alpha[j]) or post.n_aligned[j]:
                continue  # collinear on these rows with one already active
            post.add(int(j), float(alpha))
        lml, _ = post.refresh(update_beta=False, beta_cap=cap)
        log.info("MVRVM: warm start from %d basis functions, log ML %.6g", post.k, lml)
        return lml

    def _settled(self, move, post: _Posterior) -> bool:
        """Whether ``move`` proposes termination: none, or a re-estimate changing log alpha by < tol."""
        if move is None:
            return True
        j, new_alpha, _ = move
        return bool(np.isfinite(post.alpha[j]) and np.isfinite(new_alpha)) and bool(
            abs(np.log(new_alpha / post.alpha[j])) < self.tol
        )

    def _best_move(self, post: _Posterior, exhaustive: bool):
        """The move with the largest gain in log ML, as ``(basis function, new alpha, gain)``, or None.

        Active basis functions are ranked by deletion and by two uphill Newton steps (``_newton_ascent``)
        from the current alpha; the best-ranked re-estimate is then solved
        exactly (``optimal_alpha``, its global optimum). Inactive ones go through branch and bound: those
        whose ``_series_bound`` beats the best gain so far get a feasible gain and a second upper bound
        from ``_mode_bounds``; only those whose bounds both beat it are solved exactly, in batches of
        decreasing bound. With ``exhaustive``, every active function is solved exactly, every inactive
        one whose bounds beat the best addition or deletion too, and a re-estimate is returned only when
        no addition or deletion would raise the likelihood (SparseBayes's termination test).
        """
        s, q = post.factors()
        q2 = q * q
        alpha = post.alpha
        active = np.isfinite(alpha)
        usable = np.all((s > 0) & np.isfinite(s) & np.isfinite(q2), axis=1)
        act = np.flatnonzero(active & usable)
        current = np.zeros(post.n_basis)
        current[act] = _contribution(alpha[act], s[act], q2[act])
        best = [None, _MIN_GAIN]
        structural = [None, _MIN_GAIN]  # best addition or deletion

        def offer(rows, new_alpha, value):
            """Moves of basis functions ``rows`` to ``new_alpha``, where l is ``value``."""
            # no "move" of an inactive function to infinity, and the last active one is never removed: a
            # re-estimate whose optimum is alpha = inf would be a deletion, which leaves the empty model
            removal = active[rows] & (post.k <= 1)
            gain = np.where(~np.isfinite(new_alpha) & (~active[rows] | removal), -np.inf, value - current[rows])
            c = int(np.argmax(gain))
            move = (int(rows[c]), float(new_alpha[c]), float(gain[c]))
            is_structural = not active[rows[c]] or not np.isfinite(new_alpha[c])
            for record, allowed in ((best, True), (structural, is_structural)):
                if allowed and move[2] > record[1]:
                    record[:] = [move, move[2]]

        pending = act[:0]  # active rows to solve exactly along with the first batch
        if act.size:
            if post.k > 1:
                offer(act, np.full(act.size, np.inf), np.zeros(act.size))  # deletion
            if exhaustive:
                pending = act
            else:
                offer(act, *_newton_ascent(alpha[act], s[act], q2[act], _RANK_NEWTON))
                if best[0] is not None and active[best[0][0]] and np.isfinite(best[0][1]):
                    pending = np.array([best[0][0]])

        ina = np.flatnonzero(~active & usable & (post.n_aligned == 0))
        threshold = structural if exhaustive else best
        ina = ina[_series_bound(s[ina], q2[ina]) > threshold[1]]
        order, upper = ina, np.zeros(0)
        if ina.size:
            mode_value, mode_alpha, upper = _mode_bounds(s[ina], q2[ina])
            offer(ina, mode_alpha, mode_value)
            rank = np.argsort(-upper, kind="stable")
            order, upper = ina[rank], upper[rank]
        start = 0
        while True:
            chunk = order[start : start + _BATCH][upper[start : start + _BATCH] > threshold[1]]
            rows = np.concatenate([pending, chunk])
            if not rows.size:
                break
            offer(rows, *optimal_alpha(s[rows], q2[rows]))
            pending, start = act[:0], start + _BATCH
            if chunk.size < _BATCH:
                break
        if exhaustive and structural[0] is not None and self._settled(best[0], post):
            return structural[0]
        return best[0]

    def _store(self, post: _Posterior, x: np.ndarray) -> None:
        basis = post.active_basis  # after a refresh: slots 0..k-1, all live
        order = np.argsort(basis)
        basis = basis[order]
        self.has_bias_ = bool(self.bias and basis.size and basis[0] == 0)
        self.relevance_ = basis[int(self.has_bias_) :] - int(self.bias)
        self.relevance_vectors_ = x[self.relevance_]
        self.coef_ = post.mu[:, : basis.size][:, order].T.copy()
        self.alpha_ = post.alpha[basis]
        self.beta_ = post.beta.copy()
        # Sigma_p = factor diag(scale[:, p]) factor'
        self._cov_factor = post.w[order]
        self._cov_scale = post.c

    @property
    def sigma_(self) -> np.ndarray:
        """(P, K, K) posterior weight covariance per output, rows in ``coef_`` order."""
        if not hasattr(self, "coef_"):
            raise VoxposeError("MVRVM: call fit before reading sigma_")
        f = self._cov_factor
        return np.stack([(f * c) @ f.T for c in self._cov_scale.T])

    def _basis(self, X) -> np.ndarray:
        if not hasattr(self, "coef_"):
            raise VoxposeError("MVRVM: call fit before predict")
        x = as_rows(X, "MVRVM: X", self.relevance_vectors_.shape[1])
        return design_matrix(x, self.relevance_vectors_, self.kernel_width_, self.has_bias_)

    def predict(self, X, return_std: bool = False):
        """Posterior mean (n, P) (or (n,) after a 1-D fit) for inputs ``X`` (n, d).

        With ``return_std``, also the predictive standard deviation ``sqrt(1/beta_p + phi' Sigma_p phi)``
        of each output, same shape.
        """
        phi = self._basis(X)
        mean = phi @ self.coef_
        if not return_std:
            return mean[:, 0] if self._single_output else mean
        proj = phi @ self._cov_factor
        std = np.sqrt(1.0 / self.beta_ + (proj * proj) @ self._cov_scale)
        return (mean[:, 0], std[:, 0]) if self._single_output else (mean, std)


def select_kernel_width(
    X,
    Y,
    widths=None,
    scales=(0.25, 0.5, 1.0, 2.0, 4.0),
    groups=None,
    validation_fraction: float = 0.2,
    random_state=None,
    **params,
) -> tuple[float, pd.DataFrame]:
    """Choose the MVRVM kernel width on held-out *training* rows (the caller passes training data only).

    Rule: hold out rows with ``voxpose.regression.kernels.holdout_split`` (whole ``groups``, e.g. motions, when
    given); try ``widths``, or ``scales`` times the median pairwise distance of the fitting rows; fit an
    ``MVRVM(kernel_width=w, **params)`` on the fitting rows for each; keep the width with the lowest
    validation RMSE, ``sqrt(mean over rows of ||y - y_hat||^2)`` (for PCA pose coordinates this is the
    RMS angle-vector error of the reconstructed poses, since the components are orthonormal); ties go
    to the smaller width. Refit on all training rows with the chosen width afterwards, from ``start``.

    Returns
    -------
    width : the chosen kernel width.
    table : one row per width: ``scale`` (NaN for explicit widths), ``width``, ``val_rmse``,
        ``n_relevance``, ``n_iter``, ``converged``.
    start : ``(model, fit_rows)``, the chosen candidate and the rows it was fitted on, for ``MVRVM.fit``.
    """
    x = as_rows(X, "kernel width selection: X")
    y = np.asarray(Y, dtype=np.float64)
    y = as_rows(y[:, None] if y.ndim == 1 else y, "kernel width selection: Y")
    if x.shape[0] != y.shape[0]:
        raise VoxposeError(f"kernel width selection: X has {x.shape[0]} rows but Y has {y.shape[0]}")
    fit_rows, val_rows = holdout_split(x.shape[0], validation_fraction, groups, random_state)
    if widths is None:
        base = median_pairwise_distance(x[fit_rows], random_state=random_state)
        scale_list = [float(s) for s in scales]
        width_list = [check_width(s * base) for s in scale_list]
    else:
        width_list = [check_width(w) for w in np.atleast_1d(widths)]
        scale_list = [float("nan")] * len(width_list)
    if not width_list:
        raise VoxposeError("kernel width selection: no widths to try")
    rows, models = [], []
    for scale, width in zip(scale_list, width_list, strict=True):
        model = MVRVM(kernel_width=width, random_state=random_state, **params).fit(x[fit_rows], y[fit_rows])
        models.append(model)
        err = model.predict(x[val_rows]) - y[val_rows]
        rmse = float(np.sqrt(np.mean(np.sum(err * err, axis=1))))
        log.info("kernel width %.4g: validation RMSE %.4g, %d relevance vectors", width, rmse, len(model.relevance_))
        rows.append(
            {
                "scale": scale,
                "width": width,
                "val_rmse": rmse,
                "n_relevance": len(model.relevance_),
                "n_iter": model.n_iter_,
                "converged": model.converged_,
            }
        )
    table = pd.DataFrame(rows)
    best = table.sort_values(["val_rmse", "width"], kind="stable").index[0]
    return float(table.loc[best, "width"]), table, (models[best], fit_rows)
