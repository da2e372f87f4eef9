"""The shared precision of one MVRVM basis function (Section 3): the ``alpha`` maximising the marginal
likelihood over all P outputs at once, and the bounds that let training skip most candidates.

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

``series_bound`` and ``mode_bounds`` bound ``max l`` from above cheaply, and ``newton_ascent`` climbs ``l``
a few steps; ``voxpose.regression.mvrvm`` ranks its candidate moves with them (branch and bound).
"""

import numpy as np

_IMAG_TOL = 1e-6  # a root is real when |imag| <= _IMAG_TOL * |root|
_POLISH = 1  # Newton steps polishing the roots of the stationarity polynomial


def contribution(alpha, s, q2) -> np.ndarray:
    """``l(alpha)``: summed over the last axis of ``s`` and ``q2`` (..., P); ``alpha`` (...,) may be inf."""
    a = np.asarray(alpha, dtype=np.float64)[..., None]
    return 0.5 * np.sum(q2 / (a + s) - np.log1p(s / a), axis=-1)


def mode_bounds(s, q2, subdivisions: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cheap lower and upper bounds on ``max l`` for many basis functions at once; s, q2 (n, P).

    Each output's term ``l_p`` is unimodal in ``log alpha`` (it rises to its maximum at the single-output
    optimum ``s^2 / (q^2 - s)`` when ``q^2 > s``, else rises towards 0 at infinity). So between two
    consecutive points of a grid that contains these P modes, every ``l_p`` is monotone, its maximum there
    is at one end, and ``sum_p max(l_p(left), l_p(right))`` bounds ``l`` on that interval from above (below
    the smallest mode every ``l_p`` rises). The grid is the modes and infinity; with ``subdivisions`` k > 1,
    also k - 1 points evenly spaced in ``log alpha`` between consecutive modes and k - 1 beyond the largest
    (at ``e^1, e^2, e^4, ...`` times it), which tightens the bound where it matters at the cost of
    evaluating ``l`` at about k P points. ``l`` at the finite grid points gives feasible values.

    Returns
    -------
    best_value : (n,) largest ``l`` at a finite grid point (-inf when there is none).
    best_alpha : (n,) that point (inf when there is none).
    upper : (n,) upper bound on ``l`` over (0, inf].
    """
    n = s.shape[0]
    wants = q2 > s
    with np.errstate(divide="ignore"):
        mode = np.where(wants, s * s / np.where(wants, q2 - s, 1.0), np.inf)
    order = np.argsort(mode, axis=1)  # outputs in the order of their modes
    ss, qs = np.take_along_axis(s, order, 1), np.take_along_axis(q2, order, 1)
    points = np.take_along_axis(mode, order, 1)
    if subdivisions > 1:
        with np.errstate(divide="ignore", invalid="ignore"):  # rows without a mode get no extra points
            log_mode = np.log(points)
            last = np.max(np.where(np.isfinite(log_mode), log_mode, -np.inf), axis=1, keepdims=True)
            ends = np.where(np.isfinite(log_mode), log_mode, last)  # outputs without a mode: at the largest one
            frac = np.arange(1, subdivisions) / subdivisions
            inner = (ends[:, :-1, None] + np.diff(ends, axis=1)[:, :, None] * frac).reshape(n, -1)
            extra = np.exp(np.concatenate([inner, last + 2.0 ** np.arange(subdivisions - 1)], axis=1))
        extra = np.where(np.any(wants, axis=1)[:, None], extra, np.inf)
        points = np.sort(np.concatenate([points, extra], axis=1), axis=1)
    points = np.concatenate([points, np.full((n, 1), np.inf)], axis=1)
    a = points[:, :, None]
    terms = 0.5 * (qs[:, None, :] / (a + ss[:, None, :]) - np.log1p(ss[:, None, :] / a))  # (n, grid, P)
    upper = np.max(np.sum(np.maximum(terms[:, :-1], terms[:, 1:]), axis=2), axis=1)
    total = terms[:, :-1].sum(axis=2)
    finite_total = np.where(np.isfinite(points[:, :-1]), total, -np.inf)
    best = np.argmax(finite_total, axis=1)
    rows = np.arange(n)
    return finite_total[rows, best], points[rows, best], upper


def series_bound(s, q2) -> np.ndarray:
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


def slope_terms(alpha, s, q2):
    """``g = sum_p h_p`` (``dl/dlog(alpha) = g / 2``) and ``dg/dlog(alpha)``; alpha (...,), s and q2 (..., P)."""
    a = np.asarray(alpha)[..., None]
    apc = a + s
    g = np.sum((s * s + a * (s - q2)) / apc**2, axis=-1)
    dg = alpha * np.sum(((s - q2) * (s - a) - 2.0 * s * s) / apc**3, axis=-1)
    return g, dg


def newton_ascent(alpha, s, q2, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Up to ``steps`` uphill steps of ``l`` from ``alpha`` (n,), for rows of ``s``, ``q2`` (n, P).

    Safeguarded Newton steps in ``log alpha`` (where ``l`` is concave; elsewhere a step of 8 uphill),
    halved until ``l`` rises; a row stops early when no step raises ``l`` or the step is below 1e-7 (a
    local maximum). Beyond ``alpha = 1e3 max_p max(s_p, q_p^2)``, ``l`` is ``sum_p (q_p^2 - s_p) / (2 alpha)``
    to 0.1 %, monotone, so a row climbing there goes on to ``alpha = inf``. Returns the point reached
    (inf allowed) and ``l`` there, never below ``l`` at the start.
    """
    t = np.log(alpha)
    top = np.log(np.max(np.maximum(s, q2), axis=1)) + np.log(1e3)
    value = contribution(alpha, s, q2)
    gone = np.zeros(t.size, dtype=bool)
    halvings = 0.5 ** np.arange(1, 10)
    moving = np.arange(t.size)
    for _ in range(steps):
        if not moving.size:
            break
        tm, sm, qm = t[moving], s[moving], q2[moving]
        g, dg = slope_terms(np.exp(tm), sm, qm)
        leaving = (tm >= top[moving]) & (g > 0)
        gone[moving[leaving]] = True
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.clip(np.where(dg < 0, -g / dg, 8.0 * np.sign(g)), -8.0, 8.0)
        new_t = tm + step
        new_value = contribution(np.exp(new_t), sm, qm)
        failed = np.flatnonzero(~(new_value > value[moving]))
        if failed.size:  # backtrack: the first halving that raises l
            trial = tm[failed, None] + step[failed, None] * halvings
            trial_value = contribution(np.exp(trial), sm[failed, None, :], qm[failed, None, :])
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
            g, dg = slope_terms(np.exp(t), ss, qq)
            step = np.where(dg != 0.0, g / dg, 0.0)
            g_new, _ = slope_terms(np.exp(t - step), ss, qq)
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
        values = contribution(candidates, s[:, None, :], q2[:, None, :])
    values = np.where(np.isnan(candidates), -np.inf, values)
    best = np.argmax(values, axis=1)
    rows = np.arange(s.shape[0])
    alpha, value = candidates[rows, best], values[rows, best]
    # no finite candidate beats leaving the basis function out (l = 0 at infinity)
    out = ~(value > 0.0)
    return np.where(out, np.inf, alpha), np.where(out, 0.0, value)
