"""MVRVM (Section 3) against independent references: brute-force marginal likelihoods and posteriors,
a classic single-output RVM (Tipping 2001), planted noise levels, and dense searches over alpha."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.regression import mvrvm
from voxpose.regression.kernels import design_matrix, gaussian_kernel, holdout_split, median_pairwise_distance
from voxpose.regression.mvrvm import MVRVM, optimal_alpha, select_kernel_width

LOG_2PI = np.log(2 * np.pi)


def toy(n=200, noise=0.1, seed=0):
    """Three functions of one input (sinc, a line, a cosine) with Gaussian noise, and their clean values."""
    rng = np.random.default_rng(seed)
    x = np.sort(rng.uniform(-10, 10, n))[:, None]
    clean = np.stack([np.sinc(x[:, 0] / np.pi), 0.05 * x[:, 0], np.cos(x[:, 0] / 2)], axis=1)
    return x, clean + noise * rng.standard_normal(clean.shape), clean


def log_ml(phi, y, alpha, beta):
    """Brute force: sum_p log N(y_p | 0, I / beta_p + Phi A^-1 Phi')."""
    total = 0.0
    for p in range(y.shape[1]):
        c = np.eye(len(y)) / beta[p] + (phi / alpha) @ phi.T
        _, logdet = np.linalg.slogdet(c)
        total += -0.5 * (len(y) * LOG_2PI + logdet + y[:, p] @ np.linalg.solve(c, y[:, p]))
    return total


def fitted_basis(model, x_train):
    return design_matrix(x_train, model.relevance_vectors_, model.kernel_width_, model.has_bias_)


@pytest.fixture(scope="module")
def toy_fit():
    x, y, clean = toy()
    return x, y, clean, MVRVM(kernel_width=1.5).fit(x, y)


# --- the kernel basis (Eq. 3) -------------------------------------------------------------------------------


def test_kernel_width_convention_and_design_matrix():
    a = np.array([[0.0, 0.0], [3.0, 4.0]])
    k = gaussian_kernel(a, a, 5.0)  # the two rows are 5 apart: exp(-25 / (2 * 25))
    assert np.allclose(k, [[1.0, np.exp(-0.5)], [np.exp(-0.5), 1.0]])
    phi = design_matrix(a[:1], a, 5.0, bias=True)
    assert np.allclose(phi, [[1.0, 1.0, np.exp(-0.5)]])


def test_median_pairwise_distance():
    x = np.array([[0.0], [1.0], [3.0], [7.0]])  # distances 1, 3, 7, 2, 6, 4: median 3.5
    assert median_pairwise_distance(x) == pytest.approx(3.5)
    big = np.random.default_rng(0).standard_normal((300, 2))
    sub = median_pairwise_distance(big, max_rows=100, random_state=1)
    assert sub == median_pairwise_distance(big, max_rows=100, random_state=1)
    assert sub == pytest.approx(median_pairwise_distance(big), rel=0.15)


def test_holdout_split_partitions_rows():
    fit_rows, val_rows = holdout_split(50, 0.2, random_state=0)
    assert len(val_rows) == 10 and np.array_equal(np.sort(np.concatenate([fit_rows, val_rows])), np.arange(50))
    groups = np.repeat(["a", "b", "c", "d"], [5, 20, 15, 10])
    fit_rows, val_rows = holdout_split(50, 0.3, groups=groups, random_state=0)
    assert set(groups[fit_rows]).isdisjoint(groups[val_rows]) and len(val_rows) >= 15
    with pytest.raises(VoxposeError, match="2 distinct groups"):
        holdout_split(3, 0.5, groups=["a", "a", "a"])


# --- the shared-alpha optimisation ------------------------------------------------------------------------


def grid_max(s, q2):
    """Largest l on a dense grid of log alpha, refined once around the best grid point."""
    grid = np.exp(np.linspace(-30, 30, 12001))
    values = mvrvm._contribution(grid[:, None], s[None, :], q2[None, :])
    best = int(np.argmax(values))
    fine = np.exp(np.linspace(np.log(grid[max(best - 1, 0)]), np.log(grid[min(best + 1, grid.size - 1)]), 2001))
    return max(values.max(), mvrvm._contribution(fine[:, None], s[None, :], q2[None, :]).max(), 0.0)


@pytest.mark.parametrize("p", [1, 2, 3, 8])
def test_optimal_alpha_beats_a_dense_grid(p):
    rng = np.random.default_rng(p)
    s = np.exp(rng.normal(0, 1.5, size=(25, p)))
    q2 = s * np.exp(rng.normal(0.3, 1.2, size=(25, p)))
    alpha, value = optimal_alpha(s, q2)
    for i in range(25):
        best = grid_max(s[i], q2[i])
        assert value[i] >= best - 1e-7 * max(1.0, best)
        expected = 0.0 if np.isinf(alpha[i]) else mvrvm._contribution(alpha[i], s[i], q2[i])
        assert value[i] == pytest.approx(expected, rel=1e-12, abs=1e-12)


def test_optimal_alpha_single_output_is_tipping_faul():
    s = np.array([[2.0], [2.0], [1.0]])
    q2 = np.array([[6.0], [1.0], [1.0]])
    alpha, _ = optimal_alpha(s, q2)
    assert alpha[0] == pytest.approx(4.0 / 4.0)  # s^2 / (q^2 - s)
    assert np.isinf(alpha[1]) and np.isinf(alpha[2])  # q^2 <= s: leave out


def test_optimal_alpha_finds_the_better_of_two_maxima():
    # two outputs wanting very different alphas: l has two local maxima, the higher one must be found
    s = np.array([[1.0, 1.0]])
    q2 = np.array([[1e4, 3.0]])
    alpha, value = optimal_alpha(s, q2)
    assert value[0] == pytest.approx(grid_max(s[0], q2[0]), rel=1e-9)


def test_bounds_enclose_the_maximum():
    rng = np.random.default_rng(5)
    s = np.exp(rng.normal(0, 1, size=(100, 4))) * np.exp(rng.normal(0, 2, size=(100, 1)))
    q2 = s * np.exp(rng.normal(-0.3, 1.0, size=(100, 4)))
    best = np.array([grid_max(a, b) for a, b in zip(s, q2, strict=True)])
    mode_value, mode_alpha, upper = mvrvm._mode_bounds(s, q2)
    assert np.all(upper >= best - 1e-9)
    assert np.all(mvrvm._series_bound(s, q2) >= best - 1e-9)
    finite = np.isfinite(mode_alpha)
    assert np.all(mode_value[finite] <= best[finite] + 1e-12)
    assert np.allclose(mode_value[finite], mvrvm._contribution(mode_alpha[finite], s[finite], q2[finite]))


def test_newton_ascent_reaches_a_local_maximum():
    rng = np.random.default_rng(6)
    s = np.exp(rng.normal(0, 1, size=(50, 3)))
    q2 = s * np.exp(rng.normal(0.5, 1.0, size=(50, 3)))
    start = np.exp(rng.normal(0, 2, size=50))
    alpha, value = mvrvm._newton_ascent(start, s, q2, steps=60)
    two_alpha, two_value = mvrvm._newton_ascent(start, s, q2, steps=2)
    assert np.all(two_value >= mvrvm._contribution(start, s, q2)) and np.all(value >= two_value)
    assert np.all(value >= mvrvm._contribution(start, s, q2))
    finite = np.isfinite(alpha)
    slope, curvature = mvrvm._slope_terms(alpha[finite], s[finite], q2[finite])
    assert np.allclose(slope, 0.0, atol=1e-6)
    assert np.all(curvature < 0)


# --- the incremental posterior -------------------------------------------------------------------------------


def test_incremental_factors_match_brute_force():
    """S, Q and mu after adds, re-estimates and deletes equal their definitions via C_p (before and after
    the refresh that folds the rank-one terms), and the log ML changes by exactly the predicted gains."""
    x, y, _ = toy(n=40, seed=1)
    x[5] = x[4] + 1e-3  # rows 4 and 5 (basis functions 5 and 6) are near duplicates: aligned
    phi = design_matrix(x, x, 1.5, bias=True)
    beta = np.array([50.0, 200.0, 80.0])
    cap = np.full(3, 1e12)
    post = mvrvm._Posterior(phi, y, beta, alignment_max=0.999)
    lml, _ = post.refresh(update_beta=False, beta_cap=cap)
    moves = [("add", 0, 0.5), ("add", 11, 2.0), ("add", 30, 0.1), ("re", 11, 7.0), ("add", 5, 3.0)]
    moves += [("add", 21, 1.0), ("del", 0, None), ("re", 30, 0.02), ("del", 5, None), ("add", 6, 2.0)]
    moves += [("del", 21, None)]
    six_tracked = [True] * 4 + [False] * 4 + [True] * 3  # excluded while its duplicate 5 is active
    for (kind, j, alpha), tracked in zip(moves, six_tracked, strict=True):
        s, q = post.factors()
        current = 0.0 if kind == "add" else mvrvm._contribution(post.alpha[j], s[j], q[j] ** 2)
        new = 0.0 if kind == "del" else mvrvm._contribution(alpha, s[j], q[j] ** 2)
        {"add": post.add, "re": post.reestimate, "del": lambda j, _: post.delete(j)}[kind](j, alpha)
        lml += new - current
        assert post.tracked[6] == tracked
    act = post.active_basis
    assert sorted(act) == [6, 11, 30]
    assert lml == pytest.approx(log_ml(phi[:, act], y, post.alpha[act], post.beta), rel=1e-11)

    def check():
        live = np.flatnonzero(post.live[: post.n_slots])
        pa = phi[:, act]
        rows = post.rows
        assert 5 not in rows  # aligned with the active 6
        for p in range(3):
            c_inv = np.linalg.inv(np.eye(40) / beta[p] + (pa / post.alpha[act]) @ pa.T)
            s_ref = np.einsum("nb,nm,mb->b", phi, c_inv, phi)
            assert np.allclose(post.S[rows, p], s_ref[rows], rtol=1e-9)
            assert np.allclose(post.Q[rows, p], (phi.T @ c_inv @ y[:, p])[rows], rtol=1e-9, atol=1e-9)
            sigma = np.linalg.inv(np.diag(post.alpha[act]) + beta[p] * pa.T @ pa)
            assert np.allclose(post.mu[p, live], beta[p] * sigma @ pa.T @ y[:, p], rtol=1e-9, atol=1e-9)
            assert np.allclose(post.diag[p, live], np.diag(sigma), rtol=1e-9)

    check()
    refreshed, _ = post.refresh(update_beta=False, beta_cap=cap)
    assert refreshed == pytest.approx(lml, rel=1e-11)
    act = post.active_basis
    check()


def test_noise_update_keeps_the_best_of_old_mackay_and_em():
    x, y, _ = toy(n=60, seed=2)
    phi = design_matrix(x, x, 1.5, bias=True)
    cap = np.full(3, 1e12)
    post = mvrvm._Posterior(phi, y, np.array([1e4, 1.0, 3.0]), alignment_max=0.999)
    post.refresh(update_beta=False, beta_cap=cap)
    for j, alpha in ((0, 1.0), (20, 0.3), (40, 0.3)):
        post.add(j, alpha)
    before, _ = post.refresh(update_beta=False, beta_cap=cap)
    act, old = post.active_basis, post.beta.copy()
    pa, alpha = phi[:, act], post.alpha[act]
    after, change = post.refresh(update_beta=True, beta_cap=cap)
    assert after >= before
    assert change == pytest.approx(np.max(np.abs(np.log(post.beta / old))))
    for p in range(3):
        sigma = np.linalg.inv(np.diag(alpha) + old[p] * pa.T @ pa)
        mu = old[p] * sigma @ pa.T @ y[:, p]
        resid2 = np.sum((y[:, p] - pa @ mu) ** 2)
        gamma = np.sum(1 - alpha * np.diag(sigma))
        options = [old[p], (60 - gamma) / resid2, 60 / (resid2 + gamma / old[p])]
        values = [log_ml(pa, y[:, [p]], alpha, np.array([b])) for b in options]
        assert post.beta[p] == pytest.approx(options[int(np.argmax(values))], rel=1e-9)
    assert after == pytest.approx(log_ml(pa, y, alpha, post.beta), rel=1e-10)


# --- the estimator ---------------------------------------------------------------------------------------------


def test_recovers_noise_and_functions(toy_fit):
    x, y, clean, model = toy_fit
    assert model.converged_
    noise = 1 / np.sqrt(model.beta_)
    assert np.all(np.abs(noise - 0.1) < 0.02)  # within 20 % per output
    assert len(model.relevance_) + model.has_bias_ < 40  # far fewer than 200 rows
    xt = np.linspace(-9.5, 9.5, 300)[:, None]
    clean_t = np.stack([np.sinc(xt[:, 0] / np.pi), 0.05 * xt[:, 0], np.cos(xt[:, 0] / 2)], axis=1)
    rmse = np.sqrt(np.mean((model.predict(xt) - clean_t) ** 2, axis=0))
    assert np.all(rmse < 0.1)


def test_likelihood_trace_is_monotone_and_exact(toy_fit):
    x, y, _, model = toy_fit
    trace = model.log_marginal_likelihood_
    assert len(trace) == model.n_iter_ + 1
    assert np.all(np.diff(trace) >= -1e-9 * np.abs(trace[1:]))
    phi = fitted_basis(model, x)
    assert trace[-1] == pytest.approx(log_ml(phi, y, model.alpha_, model.beta_), rel=1e-9)


def test_posterior_and_predictive_std_are_exact(toy_fit):
    x, y, _, model = toy_fit
    phi = fitted_basis(model, x)
    xt = np.array([[-3.3], [0.1], [7.0]])
    phit = fitted_basis(model, xt)
    mean, std = model.predict(xt, return_std=True)
    for p in range(3):
        sigma = np.linalg.inv(np.diag(model.alpha_) + model.beta_[p] * phi.T @ phi)
        mu = model.beta_[p] * sigma @ phi.T @ y[:, p]
        assert np.allclose(model.coef_[:, p], mu, rtol=1e-8, atol=1e-10)
        assert np.allclose(model.sigma_[p], sigma, rtol=1e-8, atol=1e-12)
        assert np.allclose(mean[:, p], phit @ mu)
        assert np.allclose(std[:, p], np.sqrt(1 / model.beta_[p] + np.einsum("ni,ij,nj->n", phit, sigma, phit)))


def test_deterministic(toy_fit):
    x, y, _, model = toy_fit
    again = MVRVM(kernel_width=1.5).fit(x, y)
    assert np.array_equal(again.relevance_, model.relevance_)
    assert np.array_equal(again.coef_, model.coef_)
    assert np.array_equal(again.log_marginal_likelihood_, model.log_marginal_likelihood_)


def classic_step(phi, t, alpha, beta):
    """One re-estimation of Tipping (2001): alpha_i = gamma_i / mu_i^2, beta = (N - sum gamma) / ||t - Phi mu||^2."""
    h = np.diag(alpha) + beta * phi.T @ phi
    factor = np.linalg.cholesky(h)
    sigma = np.linalg.solve(factor.T, np.linalg.solve(factor, np.eye(len(alpha))))
    mu = beta * sigma @ phi.T @ t
    gamma = 1 - alpha * np.diag(sigma)
    return gamma / mu**2, (len(t) - gamma.sum()) / np.sum((t - phi @ mu) ** 2), mu


def reference_rvm(phi, t, iterations=3000):
    """Tipping (2001): re-estimate all alphas and beta together from alpha = 1e-3, pruning alpha > 1e9."""
    keep = np.arange(phi.shape[1])
    alpha, beta = np.full(keep.size, 1e-3), 100.0 / t.var()
    for _ in range(iterations):
        new_alpha, beta, _ = classic_step(phi[:, keep], t, alpha, beta)
        done = np.max(np.abs(np.log(new_alpha / alpha))) < 1e-6
        small = new_alpha < 1e9
        keep, alpha = keep[small], new_alpha[small]
        if done:
            break
    return keep, classic_step(phi[:, keep], t, alpha, beta)[2], beta


def test_single_output_agrees_with_classic_rvm():
    x, y, clean = toy(n=100, seed=4)
    t = y[:, 0]
    model = MVRVM(kernel_width=1.5).fit(x, t)
    phi = design_matrix(x, x, 1.5, bias=True)
    keep, mu, beta = reference_rvm(phi, t)
    xt = np.linspace(-9.5, 9.5, 200)[:, None]
    ref = design_matrix(xt, x, 1.5, bias=True)[:, keep] @ mu
    ours = model.predict(xt)
    assert ours.shape == (200,)
    # two local optima of the same likelihood (relevance vectors may sit on neighbouring rows)
    assert np.sqrt(np.mean((ours - ref) ** 2)) < 0.4 * 0.1
    assert 1 / np.sqrt(model.beta_[0]) == pytest.approx(1 / np.sqrt(beta), rel=0.1)
    assert 0.5 * len(keep) <= len(model.relevance_) + model.has_bias_ <= 2 * len(keep)
    # and ours is a fixed point of the classic re-estimation, up to the tolerances of both
    alpha, beta_next, mu_next = classic_step(fitted_basis(model, x), t, model.alpha_, model.beta_[0])
    assert np.max(np.abs(np.log(alpha / model.alpha_))) < 5 * model.tol
    assert beta_next == pytest.approx(model.beta_[0], rel=1e-5)
    assert np.allclose(mu_next, model.coef_[:, 0])


def test_noise_free_targets_hit_the_noise_cap():
    x, _, _ = toy(n=60, seed=5)
    phi = design_matrix(x, x, 2.0, bias=False)
    y = phi[:, [10, 40]] @ np.array([[1.0, -0.5], [0.5, 2.0]])  # exactly two basis functions
    model = MVRVM(kernel_width=2.0, bias=False, beta_max=1e6).fit(x, y)
    assert model.converged_
    assert np.allclose(model.beta_, 1e6 / y.var(axis=0))
    assert np.all(np.isfinite(model.coef_))
    assert np.allclose(model.predict(x), y, atol=1e-2 * y.std())


def test_targets_without_signal_give_the_empty_model():
    x, _, _ = toy(n=50, seed=7)
    model = MVRVM(kernel_width=1.5).fit(x, np.zeros((50, 2)))
    assert model.converged_ and model.relevance_.size == 0 and not model.has_bias_
    mean, std = model.predict(x[:3], return_std=True)
    assert np.all(mean == 0.0)
    assert np.allclose(std, 1 / np.sqrt(model.beta_))


def test_warm_start_resumes_a_fit_on_permuted_rows(toy_fit):
    x, y, _, model = toy_fit
    order = np.random.default_rng(3).permutation(len(x))  # the start model's row i is row where(order == i)
    rows = np.argsort(order)
    warm = MVRVM(kernel_width=1.5).fit(x[order], y[order], start=(model, rows))
    # it starts exactly at the converged model (same basis functions, precisions and noise) ...
    start_phi = fitted_basis(model, x)
    assert warm.log_marginal_likelihood_[0] == pytest.approx(log_ml(start_phi, y, model.alpha_, model.beta_), rel=1e-9)
    # ... and ends at least as high, on the same rows (mapped back through the permutation)
    assert warm.log_marginal_likelihood_[-1] >= model.log_marginal_likelihood_[-1] - 1e-6
    assert warm.n_iter_ < model.n_iter_
    assert set(order[warm.relevance_]) == set(model.relevance_)
    with pytest.raises(VoxposeError, match="same kernel width"):
        MVRVM(kernel_width=2.0).fit(x, y, start=(model, np.arange(len(x))))


def test_the_last_basis_function_is_never_removed():
    x, y, _ = toy(n=50, seed=7)
    one = MVRVM(kernel_width=1.5, max_iter=1).fit(x, y)  # a single move: one basis function
    assert one.alpha_.size == 1
    # on targets without signal the function's optimal alpha is infinite; as the last one it stays, pruned
    model = MVRVM(kernel_width=1.5).fit(x, np.zeros((50, 3)), start=(one, np.arange(50)))
    assert model.converged_ and model.alpha_.size == 1 and model.alpha_[0] > 1e6
    assert np.allclose(model.predict(x), 0.0, atol=1e-6)


def test_select_kernel_width_uses_held_out_rows():
    x, y, _ = toy(n=120, seed=6)
    width, table, (model, rows) = select_kernel_width(x, y, scales=(0.05, 0.5, 8.0), random_state=0)
    assert list(table["scale"]) == [0.05, 0.5, 8.0]
    assert width == table.loc[table["val_rmse"].idxmin(), "width"]
    assert table.loc[table["width"] == width, "scale"].item() == 0.5  # neither too narrow nor too wide
    assert model.kernel_width_ == width and len(rows) < 120 and len(model.relevance_) > 0  # the chosen candidate
    groups = np.repeat(np.arange(6), 20)
    width_g, table_g, _ = select_kernel_width(x, y, widths=[1.0, 2.0], groups=groups, random_state=0)
    assert width_g in (1.0, 2.0) and table_g["scale"].isna().all()


@pytest.mark.parametrize(
    "kwargs, x, y, message",
    [
        ({}, np.zeros((5, 2)), np.zeros((4, 1)), "5 rows but Y has 4"),
        ({}, np.full((5, 2), np.nan), np.zeros((5, 1)), "NaN"),
        ({}, np.zeros((5, 2)), np.full((5, 1), np.inf), "NaN or infinite"),
        ({"kernel_width": 0.0}, np.eye(5), np.zeros(5), "kernel width"),
        ({"kernel_width": -1.0}, np.eye(5), np.zeros(5), "kernel width"),
        ({}, np.ones((1, 2)), np.zeros(1), "at least 2 training rows"),
        ({"kernel": "linear"}, np.eye(5), np.zeros(5), "unknown kernel"),
        ({"max_iter": 0}, np.eye(5), np.zeros(5), "max_iter"),
        ({"tol": -1.0}, np.eye(5), np.zeros(5), "tol"),
        ({}, np.ones((5, 2)), np.zeros(5), "identical"),
    ],
)
def test_bad_input_raises(kwargs, x, y, message):
    with pytest.raises(VoxposeError, match=message):
        MVRVM(**kwargs).fit(x, y)


def test_predict_checks(toy_fit):
    with pytest.raises(VoxposeError, match="call fit"):
        MVRVM().predict(np.zeros((2, 1)))
    _, _, _, model = toy_fit
    with pytest.raises(VoxposeError, match="1 columns"):
        model.predict(np.zeros((2, 3)))
