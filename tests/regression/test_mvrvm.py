"""MVRVM (Section 3) against independent references: brute-force marginal likelihoods and posteriors,
a classic single-output RVM (Tipping 2001), planted noise levels, and dense searches over alpha."""

import json
import warnings

import numpy as np
import pytest

from tests.helpers import mvrvm_log_ml, mvrvm_toy
from voxpose.errors import ConvergenceWarning, NotFittedError, VoxposeError
from voxpose.io.hdf5 import read_arrays, write_arrays
from voxpose.regression.kernels import design_matrix, gaussian_kernel, holdout_split, median_pairwise_distance
from voxpose.regression.mvrvm import MVRVM, _best_width, select_kernel_width


def fitted_basis(model, x_train):
    return design_matrix(x_train, model.relevance_vectors_, model.kernel_width_, model.has_bias_)


@pytest.fixture(scope="module")
def toy_fit():
    x, y, clean = mvrvm_toy()
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
    assert trace[-1] == pytest.approx(mvrvm_log_ml(phi, y, model.alpha_, model.beta_), rel=1e-9)


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
    x, y, clean = mvrvm_toy(n=100, seed=4)
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
    x, _, _ = mvrvm_toy(n=60, seed=5)
    phi = design_matrix(x, x, 2.0, bias=False)
    y = phi[:, [10, 40]] @ np.array([[1.0, -0.5], [0.5, 2.0]])  # exactly two basis functions
    model = MVRVM(kernel_width=2.0, bias=False, beta_max=1e6).fit(x, y)
    assert model.converged_
    assert np.allclose(model.beta_, 1e6 / y.var(axis=0))
    assert np.all(np.isfinite(model.coef_))
    assert np.allclose(model.predict(x), y, atol=1e-2 * y.std())


def test_targets_without_signal_give_the_bias_alone_with_no_weight():
    x, _, _ = mvrvm_toy(n=50, seed=7)
    model = MVRVM(kernel_width=1.5).fit(x, np.zeros((50, 2)))
    # the fit starts from the bias, which as the last basis function is pruned (alpha -> inf) but never removed
    assert model.converged_ and model.relevance_.size == 0 and model.has_bias_ and model.alpha_[0] > 1e6
    assert np.allclose(model.coef_, 0.0, atol=1e-6)
    without_bias = MVRVM(kernel_width=1.5, bias=False).fit(x, np.zeros((50, 2)))
    assert without_bias.converged_ and without_bias.alpha_.size == 0
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
    start_lml = mvrvm_log_ml(start_phi, y, model.alpha_, model.beta_)
    assert warm.log_marginal_likelihood_[0] == pytest.approx(start_lml, rel=1e-9)
    # ... and ends at least as high, on the same rows (mapped back through the permutation)
    assert warm.log_marginal_likelihood_[-1] >= model.log_marginal_likelihood_[-1] - 1e-6
    assert warm.n_iter_ < model.n_iter_
    assert set(order[warm.relevance_]) == set(model.relevance_)
    with pytest.raises(VoxposeError, match="same kernel width"):
        MVRVM(kernel_width=2.0).fit(x, y, start=(model, np.arange(len(x))))


def test_wide_gaussians_fit_beyond_the_mean():
    """Gaussians twice as wide as the rows' spread are nearly constant, but together they still span a line and
    a parabola: the fit recovers both (planted noise 0.05) with a few relevance vectors besides the bias. (With
    uncentred alignment tests every Gaussian was collinear with the first: that fit stopped at the mean, 0.3.)"""
    rng = np.random.default_rng(0)
    x = np.sort(rng.uniform(-10, 10, 150))[:, None]
    clean = np.stack([0.05 * x[:, 0], (x[:, 0] / 10) ** 2 - 1 / 3], axis=1)
    model = MVRVM(kernel_width=40.0).fit(x, clean + 0.05 * rng.standard_normal(clean.shape))
    assert model.converged_ and model.has_bias_ and 2 <= len(model.relevance_) <= 10
    assert np.all(np.sqrt(np.mean((model.predict(x) - clean) ** 2, axis=0)) < 0.015)
    assert np.allclose(1 / np.sqrt(model.beta_), 0.05, rtol=0.15)


def test_the_last_basis_function_is_never_removed():
    x, y, _ = mvrvm_toy(n=50, seed=7)
    with pytest.warns(ConvergenceWarning):
        one = MVRVM(kernel_width=1.5, bias=False, max_iter=1).fit(x, y)  # a single move: one Gaussian
    assert one.alpha_.size == 1
    # on targets without signal the function's optimal alpha is infinite; as the last one it stays, pruned
    model = MVRVM(kernel_width=1.5, bias=False).fit(x, np.zeros((50, 3)), start=(one, np.arange(50)))
    assert model.converged_ and model.alpha_.size == 1 and model.alpha_[0] > 1e6
    assert np.allclose(model.predict(x), 0.0, atol=1e-6)


def test_select_kernel_width_uses_held_out_rows():
    x, y, _ = mvrvm_toy(n=120, seed=6)
    width, table, (model, rows) = select_kernel_width(x, y, scales=(0.05, 0.5, 8.0), random_state=0)
    assert [row["scale"] for row in table] == [0.05, 0.5, 8.0]
    assert json.loads(json.dumps(table)) == table  # plain records, as fit.json stores them
    assert width == min(table, key=lambda row: row["val_rmse"])["width"]
    assert [row["scale"] for row in table if row["width"] == width] == [0.5]  # neither too narrow nor too wide
    assert model.kernel_width_ == width and len(rows) < 120 and len(model.relevance_) > 0  # the chosen candidate
    groups = np.repeat(np.arange(6), 20)
    width_g, table_g, _ = select_kernel_width(x, y, widths=[1.0, 2.0], groups=groups, random_state=0)
    assert width_g in (1.0, 2.0) and all(np.isnan(row["scale"]) for row in table_g)


def test_best_width_prefers_lower_error_then_smaller_width_and_never_nan():
    def rows(*pairs):
        return [{"width": w, "val_rmse": e} for w, e in pairs]

    assert _best_width(rows((1.0, 3.0), (2.0, 2.0), (0.5, 4.0))) == 1  # lowest error
    assert _best_width(rows((2.0, 2.0), (1.0, 2.0))) == 1  # a tie goes to the smaller width
    assert _best_width(rows((1.0, 2.0), (1.0, 2.0))) == 0  # then to the earlier record
    assert _best_width(rows((0.5, np.nan), (1.0, 9.0))) == 1  # NaN never wins
    assert _best_width(rows((1.0, np.nan), (0.5, np.nan))) == 1  # all NaN: the smaller width


def test_select_kernel_width_on_drawn_rows_is_the_selection_on_those_rows():
    """With ``max_rows``, the same seeded rows passed directly give the same table and the same candidate (its
    rows mapped back); with at least as many ``max_rows`` as rows, nothing changes."""
    x, y, _ = mvrvm_toy(n=120, seed=6)
    groups = np.repeat(np.arange(12), 10)
    kwargs = {"scales": (0.5, 2.0), "random_state": 3}
    width, table, (model, rows) = select_kernel_width(x, y, groups=groups, max_rows=60, **kwargs)
    drawn = np.sort(np.random.default_rng(3).choice(120, size=60, replace=False))
    width_d, table_d, (model_d, rows_d) = select_kernel_width(x[drawn], y[drawn], groups=groups[drawn], **kwargs)
    assert width == width_d
    assert table == table_d
    np.testing.assert_array_equal(rows, drawn[rows_d])
    np.testing.assert_array_equal(model.coef_, model_d.coef_)
    _, table_all, (_, rows_all) = select_kernel_width(x, y, groups=groups, max_rows=120, **kwargs)
    _, table_none, (_, rows_none) = select_kernel_width(x, y, groups=groups, **kwargs)
    assert table_all == table_none
    np.testing.assert_array_equal(rows_all, rows_none)
    with pytest.raises(VoxposeError, match="max_rows"):
        select_kernel_width(x, y, max_rows=0, **kwargs)


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
        ({"max_candidates": 0}, np.eye(5), np.zeros(5), "max_candidates"),
        ({}, np.ones((5, 2)), np.zeros(5), "identical"),
    ],
)
def test_bad_input_raises(kwargs, x, y, message):
    with pytest.raises(VoxposeError, match=message):
        MVRVM(**kwargs).fit(x, y)


def test_predict_checks(toy_fit):
    unfitted = MVRVM()
    for use in (lambda: unfitted.predict(np.zeros((2, 1))), lambda: unfitted.sigma_, unfitted.to_arrays):
        with pytest.raises(NotFittedError, match=r"^MVRVM is not fitted: call fit first$"):
            use()
    _, _, _, model = toy_fit
    with pytest.raises(VoxposeError, match="1 columns"):
        model.predict(np.zeros((2, 3)))


# --- the estimator's state ----------------------------------------------------------------------------------


def test_restored_model_predicts_exactly_like_the_fitted_one(toy_fit, tmp_path):
    """to_arrays -> an HDF5 file -> from_arrays: the same means, standard deviations and covariances."""
    x, _, _, model = toy_fit
    write_arrays(tmp_path / "m.h5", "mvrvm", *model.to_arrays())
    restored = MVRVM.from_arrays(*read_arrays(tmp_path / "m.h5", "mvrvm"))
    xt = np.linspace(-12, 12, 97)[:, None]
    mean, std = model.predict(xt, return_std=True)
    restored_mean, restored_std = restored.predict(xt, return_std=True)
    np.testing.assert_allclose(restored_mean, mean, rtol=0, atol=1e-12)
    np.testing.assert_allclose(restored_std, std, rtol=0, atol=1e-12)
    np.testing.assert_allclose(restored.sigma_, model.sigma_, rtol=0, atol=1e-12)
    assert restored.kernel_width_ == model.kernel_width_
    np.testing.assert_array_equal(restored.log_marginal_likelihood_, model.log_marginal_likelihood_)


def test_restored_single_output_model_keeps_its_shapes():
    x, y, _ = mvrvm_toy(n=80, seed=3)
    model = MVRVM(kernel_width=1.5).fit(x, y[:, 0])
    restored = MVRVM.from_arrays(*model.to_arrays())
    mean, std = restored.predict(x[:7], return_std=True)
    assert mean.shape == std.shape == (7,)
    np.testing.assert_allclose(mean, model.predict(x[:7]), rtol=0, atol=1e-12)


def test_model_restored_without_covariance_predicts_means_only(toy_fit):
    x, _, _, model = toy_fit
    arrays, meta = model.to_arrays()
    means_only = MVRVM.from_arrays({k: v for k, v in arrays.items() if not k.startswith("cov_")}, meta)
    np.testing.assert_allclose(means_only.predict(x), model.predict(x), rtol=0, atol=1e-12)
    with pytest.raises(VoxposeError, match="without its posterior covariance"):
        means_only.predict(x, return_std=True)


def test_a_fit_stopped_by_max_iter_warns():
    x, y, _ = mvrvm_toy(n=80, seed=3)
    with pytest.warns(ConvergenceWarning, match=r"^MVRVM: no convergence in 1 iterations \(tol 0.001\)$"):
        stopped = MVRVM(kernel_width=1.5, max_iter=1).fit(x, y)
    assert not stopped.converged_
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        assert MVRVM(kernel_width=1.5).fit(x, y).converged_  # the same data converge given the iterations


def test_constructor_is_keyword_only_after_the_kernel_width():
    x, y, _ = mvrvm_toy(n=40, seed=1)
    assert MVRVM(1.5).fit(x, y).kernel_width_ == 1.5
    with pytest.raises(TypeError):
        MVRVM(1.5, "rbf")


# --- candidate subsets (max_candidates) --------------------------------------------------------------------------


def test_candidates_covering_every_row_are_eq3(toy_fit):
    x, y, _, model = toy_fit
    for m in (len(x), 10 * len(x)):
        covered = MVRVM(kernel_width=1.5, max_candidates=m).fit(x, y)
        assert np.array_equal(covered.relevance_, model.relevance_)
        assert np.array_equal(covered.coef_, model.coef_) and np.array_equal(covered.beta_, model.beta_)


def test_candidate_subset_fit_is_exact_on_every_row(toy_fit):
    """Gaussians on 60 random rows only, the likelihood over all 200: the final log ML is the brute-force one
    on all rows, the relevance vectors come from the drawn rows, and the functions are still recovered."""
    x, y, clean, _ = toy_fit
    model = MVRVM(kernel_width=1.5, max_candidates=60, random_state=4).fit(x, y)
    drawn = np.random.default_rng(4).choice(len(x), size=60, replace=False)
    assert model.converged_ and set(model.relevance_) <= set(drawn)
    brute = mvrvm_log_ml(fitted_basis(model, x), y, model.alpha_, model.beta_)
    assert model.log_marginal_likelihood_[-1] == pytest.approx(brute, rel=1e-9)
    assert np.all(np.abs(1 / np.sqrt(model.beta_) - 0.1) < 0.02)
    assert np.all(np.sqrt(np.mean((model.predict(x) - clean) ** 2, axis=0)) < 0.1)


def test_candidate_subset_recovers_planted_relevance_vectors():
    """Targets made of 4 Gaussians centred on drawn candidate rows, plus noise: those 4 rows are kept with
    their weights; the few others the noise buys carry almost nothing."""
    rng = np.random.default_rng(0)
    x = rng.uniform(-6, 6, size=(400, 2))
    drawn = np.random.default_rng(1).choice(len(x), size=80, replace=False)
    planted = drawn[[0, 1, 2, 3]]
    planted = planted[np.argsort(planted)]
    weights = np.array([[2.0, -1.0], [-1.5, 2.0], [1.0, 1.0], [2.5, -2.0]])
    y = gaussian_kernel(x, x[planted], 1.0) @ weights + 0.05 * rng.standard_normal((len(x), 2))
    model = MVRVM(kernel_width=1.0, max_candidates=80, random_state=1).fit(x, y)
    assert model.converged_
    assert set(planted) <= set(model.relevance_) and len(model.relevance_) <= 16
    at = np.searchsorted(model.relevance_, planted) + model.has_bias_
    assert np.allclose(model.coef_[at], weights, atol=0.05)
    assert np.max(np.abs(np.delete(model.coef_, at, axis=0))) < 0.05
    assert np.all(np.abs(1 / np.sqrt(model.beta_) - 0.05) < 0.01)


def test_candidate_subset_keeps_a_warm_start_relevance_vectors(toy_fit):
    x, y, _, model = toy_fit
    warm = MVRVM(kernel_width=1.5, max_candidates=20, random_state=0).fit(x, y, start=(model, np.arange(len(x))))
    assert warm.log_marginal_likelihood_[0] == pytest.approx(model.log_marginal_likelihood_[-1], rel=1e-9)
    assert warm.log_marginal_likelihood_[-1] >= model.log_marginal_likelihood_[-1] - 1e-6
