"""MPPCA against independent references: dense Gaussian densities, a literal Appendix C step, the spherical
Gaussian mixture update, closed-form PPCA, and planted mixtures."""

import warnings

import numpy as np
import pytest
from scipy.linalg import subspace_angles
from scipy.special import logsumexp
from scipy.stats import multivariate_normal

import voxpose.features.mppca as mppca_module
from voxpose.errors import ConvergenceWarning, NotFittedError, VoxposeError
from voxpose.features import mppca_kernels
from voxpose.features.mppca import MPPCA

# most fits here stop after a few EM steps on purpose; test_a_fit_stopped_by_max_iter_warns checks the warning
pytestmark = pytest.mark.filterwarnings("ignore::voxpose.errors.ConvergenceWarning")


def dense_log_joint(X, weights, means, components, noise):
    """log pi_i + log N(x; mu_i, W_i W_i^T + sigma_i^2 I) with dense covariances, shape (n, K)."""
    d = X.shape[1]
    return np.stack(
        [
            np.log(w) + multivariate_normal(mu, W @ W.T + s * np.eye(d)).logpdf(X)
            for w, mu, W, s in zip(weights, means, components, noise, strict=True)
        ],
        axis=1,
    )


def params(model):
    return model.weights_, model.means_, model.components_, model.noise_variance_


def overlapping_clusters(seed, n_per=150, d=5):
    """Three anisotropic Gaussian clusters that overlap, so EM has work to do."""
    rng = np.random.default_rng(seed)
    parts = []
    for _ in range(3):
        mix = rng.normal(size=(d, d))
        parts.append(2.0 * rng.normal(size=d) + rng.normal(size=(n_per, d)) @ mix)
    return np.concatenate(parts)


def closed_form_ppca(X, q):
    """Maximum-likelihood PPCA (Tipping & Bishop 1999): mean, W W^T, sigma^2, mean log-likelihood."""
    mean = X.mean(axis=0)
    S = (X - mean).T @ (X - mean) / len(X)
    eigval, eigvec = np.linalg.eigh(S)
    eigval, eigvec = eigval[::-1], eigvec[:, ::-1]
    noise = eigval[q:].mean()
    WWt = eigvec[:, :q] @ np.diag(eigval[:q] - noise) @ eigvec[:, :q].T
    d = X.shape[1]
    loglik = -0.5 * (d * np.log(2 * np.pi) + np.log(eigval[:q]).sum() + (d - q) * np.log(noise) + d)
    return mean, WWt, noise, loglik


def test_score_samples_and_responsibilities_equal_dense_covariances():
    X = overlapping_clusters(0)
    model = MPPCA(3, n_latent=2, max_iter=5, random_state=0, chunk_size=37).fit(X)
    reference = dense_log_joint(X, *params(model))
    np.testing.assert_allclose(model.score_samples(X), logsumexp(reference, axis=1), rtol=1e-10)
    np.testing.assert_allclose(
        model.predict_proba(X), np.exp(reference - logsumexp(reference, axis=1, keepdims=True)), atol=1e-10
    )
    assert model.score(X) == pytest.approx(model.log_likelihood_[-1], rel=1e-12)


def test_fit_is_translation_equivariant_far_from_the_origin():
    X = overlapping_clusters(14)
    near = MPPCA(3, n_latent=2, max_iter=10, random_state=5).fit(X)
    far = MPPCA(3, n_latent=2, max_iter=10, random_state=5).fit(X + 1e4)
    np.testing.assert_allclose(far.log_likelihood_, near.log_likelihood_, rtol=1e-8)
    np.testing.assert_allclose(far.means_ - 1e4, near.means_, atol=1e-7)
    np.testing.assert_allclose(far.noise_variance_, near.noise_variance_, rtol=1e-7)
    np.testing.assert_allclose(far.score_samples(X + 1e4), near.score_samples(X), rtol=1e-8)


def test_one_em_step_equals_literal_appendix_c_update():
    X = overlapping_clusters(1)
    start = MPPCA(3, n_latent=2, max_iter=0, random_state=4).fit(X)
    stepped = MPPCA(3, n_latent=2, max_iter=1, tol=0.0, random_state=4).fit(X)
    weights, means, components, noise = params(start)
    log_joint = dense_log_joint(X, weights, means, components, noise)
    R = np.exp(log_joint - logsumexp(log_joint, axis=1, keepdims=True))
    n, d = X.shape
    for i in range(3):
        Ni = R[:, i].sum()
        mu = R[:, i] @ X / Ni
        S = (R[:, i, None] * (X - mu)).T @ (X - mu) / Ni
        W, s2 = components[i], noise[i]
        Minv = np.linalg.inv(s2 * np.eye(2) + W.T @ W)
        W_new = S @ W @ np.linalg.inv(s2 * np.eye(2) + Minv @ W.T @ S @ W)
        s2_new = np.trace(S - S @ W @ Minv @ W_new.T) / d
        assert stepped.weights_[i] == pytest.approx(Ni / n, rel=1e-10)
        np.testing.assert_allclose(stepped.means_[i], mu, rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(stepped.components_[i], W_new, rtol=1e-8, atol=1e-10)
        assert stepped.noise_variance_[i] == pytest.approx(s2_new, rel=1e-9)
    assert not np.allclose(stepped.means_, means, atol=1e-3)  # the step moved: the comparison has teeth


def test_q0_step_equals_spherical_gaussian_mixture_update():
    X = overlapping_clusters(2)
    start = MPPCA(3, n_latent=0, max_iter=0, random_state=1).fit(X)
    stepped = MPPCA(3, n_latent=0, max_iter=1, tol=0.0, random_state=1).fit(X)
    weights, means, variances = start.weights_, start.means_, start.noise_variance_
    n, d = X.shape
    sq = ((X[:, None, :] - means[None, :, :]) ** 2).sum(axis=2)
    log_joint = np.log(weights) - 0.5 * d * np.log(2 * np.pi * variances) - sq / (2 * variances)
    R = np.exp(log_joint - logsumexp(log_joint, axis=1, keepdims=True))
    Nk = R.sum(axis=0)
    new_means = R.T @ X / Nk[:, None]
    new_var = (R * ((X[:, None, :] - new_means[None]) ** 2).sum(axis=2)).sum(axis=0) / (d * Nk)
    np.testing.assert_allclose(stepped.weights_, Nk / n, rtol=1e-10)
    np.testing.assert_allclose(stepped.means_, new_means, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(stepped.noise_variance_, new_var, rtol=1e-10)
    assert stepped.components_.shape == (3, X.shape[1], 0)
    assert start.log_likelihood_[0] == pytest.approx(logsumexp(log_joint, axis=1).mean(), rel=1e-12)


def test_single_component_is_closed_form_ppca():
    rng = np.random.default_rng(3)
    X = rng.normal(size=(2000, 6)) @ rng.normal(size=(6, 6)) + rng.normal(size=6)
    model = MPPCA(1, n_latent=2, max_iter=5, tol=0.0, random_state=0).fit(X)
    mean, WWt, noise, loglik = closed_form_ppca(X, 2)
    W = model.components_[0]
    np.testing.assert_allclose(model.means_[0], mean, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(W @ W.T, WWt, rtol=1e-8, atol=1e-10)
    assert model.noise_variance_[0] == pytest.approx(noise, rel=1e-8)
    np.testing.assert_allclose(model.log_likelihood_, loglik, rtol=1e-10)
    assert model.n_iter_ >= 1  # at least one EM step, which kept the maximum-likelihood fixed point


def planted_mixture(seed, counts, d=12, q=2, noise=0.05):
    """Well-separated PPCA components with planted subspaces; returns X, labels, means, bases, noise."""
    rng = np.random.default_rng(seed)
    K = len(counts)
    means = 15.0 * rng.standard_normal((K, d))
    bases = [np.linalg.qr(rng.standard_normal((d, q)))[0] for _ in range(K)]
    scales = np.array([3.0, 1.5])
    parts = [
        means[k] + (rng.standard_normal((n, q)) * scales) @ bases[k].T + np.sqrt(noise) * rng.standard_normal((n, d))
        for k, n in enumerate(counts)
    ]
    labels = np.repeat(np.arange(K), counts)
    order = rng.permutation(labels.size)
    return np.concatenate(parts)[order], labels[order], means, bases, noise


def test_planted_mixture_is_recovered():
    counts = [400, 800, 1200, 1600]
    X, labels, means, bases, noise = planted_mixture(5, counts)
    model = MPPCA(4, n_latent=2, random_state=2).fit(X)
    assert model.converged_
    match = [int(np.argmin(((model.means_ - m) ** 2).sum(axis=1))) for m in means]
    assert sorted(match) == [0, 1, 2, 3]
    for k, i in enumerate(match):
        group = X[labels == k]
        mean, WWt, group_noise, _ = closed_form_ppca(group, 2)
        # separated components: EM reaches each group's own maximum-likelihood PPCA
        assert model.weights_[i] == pytest.approx(counts[k] / len(X), abs=1e-6)
        np.testing.assert_allclose(model.means_[i], mean, atol=1e-6)
        np.testing.assert_allclose(model.components_[i] @ model.components_[i].T, WWt, atol=1e-5)
        # and the planted parameters, up to sampling error
        assert np.max(subspace_angles(model.components_[i], bases[k])) < 0.05
        assert model.noise_variance_[i] == pytest.approx(noise, rel=0.1)
    assert model.n_reseeded_ == 0


def test_log_likelihood_never_decreases():
    X = overlapping_clusters(6, n_per=200)
    model = MPPCA(4, n_latent=1, max_iter=40, tol=0.0, random_state=0).fit(X)
    history = np.array(model.log_likelihood_)
    assert model.n_reseeded_ == 0 and len(history) == 41
    assert np.diff(history).min() >= -1e-12 * np.abs(history).max()
    assert history[-1] - history[0] > 1e-3  # EM did improve on the initialisation


def test_same_seed_gives_identical_fit_and_chunking_does_not_matter():
    X = overlapping_clusters(7)
    a = MPPCA(3, n_latent=2, max_iter=10, random_state=11, chunk_size=13).fit(X)
    b = MPPCA(3, n_latent=2, max_iter=10, random_state=11, chunk_size=13).fit(X)
    c = MPPCA(3, n_latent=2, max_iter=10, random_state=11, chunk_size=len(X)).fit(X)
    for x, y in zip(params(a), params(b), strict=True):
        np.testing.assert_array_equal(x, y)
    assert a.log_likelihood_ == b.log_likelihood_
    for x, y in zip(params(a), params(c), strict=True):
        np.testing.assert_allclose(x, y, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(a.log_likelihood_, c.log_likelihood_, rtol=1e-12)


@pytest.mark.parametrize("dataset", ["separated", "overlapping"])
def test_sparse_and_dense_statistics_agree(monkeypatch, dataset):
    X = planted_mixture(15, [300, 300, 300])[0] if dataset == "separated" else overlapping_clusters(15)
    model = MPPCA(3, n_latent=2, max_iter=3, random_state=0).fit(X)
    proj = mppca_module._project(mppca_module._Params(*params(model)))
    stats = {}
    for path, fraction in [("sparse", 1.0), ("dense", 0.0)]:
        monkeypatch.setattr(mppca_module, "_SPARSE_FRACTION", fraction)
        stats[path] = mppca_module._accumulate(X, proj, chunk_size=50)
    for a, b in zip(stats["sparse"], stats["dense"], strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-9)
    R = model.predict_proba(X)
    np.testing.assert_allclose(stats["sparse"].counts, R.sum(axis=0), rtol=1e-12)
    np.testing.assert_allclose(stats["sparse"].sums, R.T @ (X - proj.offset), rtol=1e-10, atol=1e-9)


def test_noise_variance_floor_holds_a_collapsed_component():
    rng = np.random.default_rng(8)
    X = np.concatenate([rng.normal(size=(200, 4)), np.tile([20.0, 20.0, 20.0, 20.0], (50, 1))])
    model = MPPCA(2, n_latent=1, min_noise_variance=1e-6, random_state=0).fit(X)
    assert model.noise_variance_floor_ == pytest.approx(1e-6 * np.var(X, axis=0).mean(), rel=1e-12)
    collapsed = int(np.argmin(((model.means_ - 20.0) ** 2).sum(axis=1)))
    assert model.noise_variance_[collapsed] == model.noise_variance_floor_
    assert model.noise_variance_[1 - collapsed] > 0.5
    assert np.isfinite(model.score_samples(X)).all()


def test_starved_component_is_reseeded_once_then_left_to_its_rows(caplog):
    rng = np.random.default_rng(9)
    outlier = [1000.0, 1000.0, 1000.0]
    X = np.concatenate([rng.normal(size=(300, 3)), 10.0 + rng.normal(size=(300, 3)), [outlier]])
    with caplog.at_level("INFO", logger="voxpose.features.mppca"):
        model = MPPCA(3, n_latent=2, max_iter=50, random_state=0).fit(X)
    # k-means++ seeds a centre on the outlier; its one-row cluster cannot support q = 2 and is re-seeded ...
    assert "initialisation: re-seeded 1 starved" in caplog.text
    # ... EM pulls a component back onto the outlier, which is then kept, its variance held by the floor
    assert 1 <= model.n_reseeded_ <= 3 and model.converged_  # each slot re-seeded at most once
    on_outlier = int(np.argmin(((model.means_ - outlier) ** 2).sum(axis=1)))
    np.testing.assert_allclose(model.means_[on_outlier], outlier, atol=1e-6)
    assert model.noise_variance_[on_outlier] == model.noise_variance_floor_
    np.testing.assert_allclose(np.sort(model.predict_proba(X).sum(axis=0)), [1, 300, 300], atol=1e-6)


def test_reseed_splits_the_heaviest_component_along_its_principal_axis():
    W = np.zeros((3, 4, 1))
    W[1, :, 0] = [0.0, 3.0, 0.0, 0.0]  # the heaviest component's principal axis is e_2 with variance 9 + 1
    start = mppca_module._Params(np.array([0.1, 0.6, 0.3]), np.arange(12.0).reshape(3, 4), W, np.array([1.0, 1.0, 2.0]))
    split = mppca_module._reseed(start, np.array([True, False, False]), np.random.default_rng(0))
    shift = np.sqrt(2 / np.pi * 10.0) * np.array([0.0, 1.0, 0.0, 0.0])
    moved = split.means[0] - start.means[1]
    np.testing.assert_allclose(moved * np.sign(moved[1]), shift, atol=1e-12)  # u is defined up to sign
    np.testing.assert_allclose(split.means[1] - start.means[1], -moved, atol=1e-12)
    np.testing.assert_allclose(split.weights, np.array([0.3, 0.3, 0.3]) / 0.9)
    np.testing.assert_array_equal(split.components[0], W[1])
    assert split.noise_variance[0] == 1.0
    np.testing.assert_array_equal(split.means[2], start.means[2])


def test_component_that_loses_all_rows_during_em_is_reseeded(monkeypatch, caplog):
    X, labels, means, _, _ = planted_mixture(13, [500, 500])
    real_initialise = mppca_module._initialise

    def stranded(X, n_components, n_latent, chunk_size, rng):
        params, starved = real_initialise(X, 2, n_latent, chunk_size, rng)
        far = mppca_module._Params(
            np.append(params.weights, 1e-3),
            np.vstack([params.means, np.full(X.shape[1], 1e4)]),
            np.concatenate([params.components, params.components[:1]]),
            np.append(params.noise_variance, 1.0),
        )
        return far, np.append(starved, False)

    monkeypatch.setattr(mppca_module, "_initialise", stranded)
    with caplog.at_level("INFO", logger="voxpose.features.mppca"):
        model = MPPCA(3, n_latent=2, max_iter=50, random_state=0).fit(X)
    assert "EM iteration 1: " in caplog.text and "re-seeded 1" in caplog.text
    assert 1 <= model.n_reseeded_ <= 3 and model.converged_  # each slot re-seeded at most once
    assert np.all(np.linalg.norm(model.means_, axis=1) < 100.0)  # nobody left stranded at 1e4
    np.testing.assert_allclose(model.predict_proba(X).sum(axis=0).sum(), len(X))
    assert model.predict_proba(X).sum(axis=0).min() > 3


GOOD = np.random.default_rng(12).normal(size=(40, 4))


@pytest.mark.parametrize(
    ("X", "kwargs", "message"),
    [
        (np.where(np.arange(160).reshape(40, 4) == 13, np.nan, GOOD), {}, "row 3 contains NaN"),
        (np.where(np.arange(160).reshape(40, 4) == 41, np.inf, GOOD), {}, "row 10 contains NaN or infinite"),
        (GOOD[:8], {}, "needs at least 9 rows"),
        (GOOD, {"n_latent": 4}, "n_latent"),
        (GOOD, {"n_latent": -1}, "n_latent"),
        (GOOD, {"n_components": 0}, "n_components"),
        (GOOD, {"init": "random"}, "init"),
        (GOOD, {"min_noise_variance": 0.0}, "min_noise_variance"),
        (GOOD, {"max_iter": -1}, "max_iter"),
        (GOOD, {"tol": np.nan}, "tol"),
        (GOOD, {"chunk_size": 0}, "chunk_size"),
        (np.ones((40, 4)), {"n_components": 1}, "zero variance"),
        (GOOD[:, 0], {}, "2-D"),
    ],
)
def test_bad_fit_input_raises(X, kwargs, message):
    settings = {"n_components": 3, "n_latent": 2, "random_state": 0} | kwargs
    with pytest.raises(VoxposeError, match=message):
        MPPCA(**settings).fit(X)


def test_scoring_checks_fit_and_dimension():
    unfitted = MPPCA(2)
    for use in (unfitted.score_samples, unfitted.predict_proba, unfitted.score):
        with pytest.raises(NotFittedError, match=r"^MPPCA is not fitted: call fit first$"):
            use(GOOD)
    with pytest.raises(NotFittedError, match="MPPCA is not fitted"):
        unfitted.to_arrays()
    model = MPPCA(2, n_latent=1, max_iter=2, random_state=0).fit(GOOD)
    for method in (model.score_samples, model.predict_proba, model.score):
        with pytest.raises(VoxposeError, match="MPPCA input: expected 4 columns, got 5"):
            method(np.zeros((3, 5)))
    with pytest.raises(VoxposeError, match="row 1"):
        model.predict_proba(np.array([[0.0, 0, 0, 0], [0, np.nan, 0, 0]]))


def test_restored_model_scores_exactly_like_the_fitted_one():
    X, _, _, _, _ = planted_mixture(1, [300, 500])
    model = MPPCA(2, n_latent=2, random_state=0).fit(X)
    restored = MPPCA.from_arrays(*model.to_arrays())
    np.testing.assert_array_equal(restored.predict_proba(X), model.predict_proba(X))
    np.testing.assert_array_equal(restored.score_samples(X), model.score_samples(X))
    assert (restored.n_components, restored.n_latent) == (2, 2)
    for name in ("log_likelihood_", "n_iter_", "converged_", "n_reseeded_", "noise_variance_floor_"):
        assert getattr(restored, name) == getattr(model, name), name


def test_a_fit_stopped_by_max_iter_warns():
    X = overlapping_clusters(6, n_per=200)  # EM needs 18 steps here
    with pytest.warns(ConvergenceWarning, match=r"^MPPCA: no convergence in 1 EM iterations \(tol 0.0001\)$"):
        assert not MPPCA(3, n_latent=2, max_iter=1, random_state=0).fit(X).converged_
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        assert MPPCA(3, n_latent=2, random_state=0).fit(X).converged_  # the same data converge given the steps
        MPPCA(3, n_latent=2, max_iter=0, random_state=0).fit(X)  # no EM asked for: nothing to warn about


def test_constructor_is_keyword_only_after_n_components():
    assert MPPCA(3).n_components == 3
    with pytest.raises(TypeError):
        MPPCA(3, 2)


@pytest.mark.parametrize("live_fraction", [0.0, 0.01, 0.3, 0.9])
def test_exp_skipping_underflow_is_numpys_exp_bit_for_bit(live_fraction):
    """Sparse (most entries underflow) and dense regimes, the subnormal range, the threshold, -inf and NaN."""
    rng = np.random.default_rng(3)
    a = np.where(
        rng.random((300, 40)) < live_fraction, rng.uniform(-760.0, 0.0, (300, 40)), -rng.uniform(700, 1e6, (300, 40))
    )
    a.flat[:6] = [mppca_module._EXP_ZERO, np.nextafter(mppca_module._EXP_ZERO, 0), -745.13, -720.0, -np.inf, np.nan]
    expected = np.exp(a)
    assert expected.flat[0] == 0.0 and expected.flat[2] > 0.0  # the threshold underflows, the subnormal range not
    np.testing.assert_array_equal(mppca_module._exp(a), expected)


def test_projection_is_cached_per_parameter_set():
    X = overlapping_clusters(4)
    model = MPPCA(3, n_latent=2, max_iter=3, random_state=0).fit(X)
    first = model.predict_proba(X)
    assert model._projection() is model._projection()  # computed once
    np.testing.assert_array_equal(model.predict_proba(X), first)
    with pytest.raises(ValueError, match="read-only"):  # parameters change only by being replaced ...
        model.means_[0, 0] += 1.0
    model.means_ = model.means_ + 1.0  # ... which the cache notices
    fresh = MPPCA.from_arrays(*model.to_arrays())
    np.testing.assert_array_equal(model.predict_proba(X), fresh.predict_proba(X))
    assert not np.array_equal(model.predict_proba(X), first)


@pytest.mark.parametrize(("n_latent", "dim"), [(0, 5), (2, 5), (9, 12)])  # q = 9: two blocks of accumulators
def test_compiled_posterior_equals_dense_covariances_and_the_numpy_path(monkeypatch, n_latent, dim):
    """``compiled=True``: the same densities and responsibilities as the dense reference and the numpy path (to
    rounding: it divides by the row's sum of exp instead of subtracting log p, and evaluates only the components
    its float32 screen keeps; the others are below 1e-30 on the numpy path), across chunks, on rows far from
    every component (most terms underflow) and near them; ``VOXPOSE_KERNELS=numpy`` falls back."""
    X = overlapping_clusters(5, d=dim)
    model = MPPCA(3, n_latent=n_latent, max_iter=4, random_state=0, chunk_size=41).fit(X)
    far = X[:50] * 40.0  # hundreds of nats between components: exact zeros in the responsibilities
    rows = np.concatenate([X, far])
    reference = dense_log_joint(rows, *params(model))
    log_p = logsumexp(reference, axis=1)
    compiled = MPPCA.from_arrays(*model.to_arrays())
    compiled.compiled = True
    proba, score = compiled.proba_and_score(rows)
    np.testing.assert_allclose(score, log_p, rtol=1e-10)
    np.testing.assert_allclose(proba, np.exp(reference - log_p[:, None]), atol=1e-10)
    numpy_proba, numpy_score = model.proba_and_score(rows)
    kept = proba > 0.0
    np.testing.assert_allclose(proba[kept], numpy_proba[kept], rtol=1e-12)
    assert numpy_proba[~kept].max(initial=0.0) < 1e-30  # screened: provably below 1e-30
    np.testing.assert_allclose(score, numpy_score, rtol=1e-12)
    assert np.count_nonzero(proba[len(X) :] == 0.0) > 0
    np.testing.assert_allclose(compiled.score_samples(rows), numpy_score, rtol=1e-12)
    monkeypatch.setenv("VOXPOSE_KERNELS", "numpy")
    np.testing.assert_array_equal(compiled.proba_and_score(rows)[0], numpy_proba)


def test_float32_screen_keeps_every_component_above_1e_30_where_rounding_is_tens_of_nats():
    """The compiled path's screen (features/mppca_kernels.py) on rows built so that float32 rounding moves log joints
    by tens of nats: two components 1 apart with sigma^2 = 1e-9 and rows near the plane between them, where both
    are live (responsibilities from 1 down past 1e-30). Every component whose responsibility on the float64 numpy
    path is at least 1e-30 is kept and equals it, every screened one is below 1e-30; and the same screen without
    its error allowance (gamma = 0) does drop live components, so the data tests the allowance."""
    rng = np.random.default_rng(3)
    d, q = 40, 2
    axis = rng.normal(size=d)
    axis /= np.linalg.norm(axis)
    means = np.stack([0.5 * axis, -0.5 * axis, 3.0 * axis + 2.0])  # the third is far from every row
    components = rng.normal(size=(3, d, q)) * 1e-9  # next to sigma, no preferred direction to speak of
    arrays = {"weights": np.full(3, 1.0 / 3.0), "means": means, "components": components,
              "noise_variance": np.full(3, 1e-9)}  # fmt: skip
    meta = {"log_likelihood": [0.0], "n_iter": 0, "converged": True, "n_reseeded": 0, "noise_variance_floor": 1e-12}
    across = rng.normal(size=(600, d)) * 0.3
    across -= np.outer(across @ axis, axis)  # in the plane between the two components ...
    rows = across + np.outer(rng.uniform(-1e-7, 1e-7, size=600), axis)  # ... give or take +-100 nats
    numpy_proba, numpy_score = MPPCA.from_arrays(arrays, meta).proba_and_score(rows)
    live = numpy_proba >= 1e-30
    assert np.count_nonzero(live.sum(axis=1) > 1) > 100
    compiled = MPPCA.from_arrays(arrays, meta)
    compiled.compiled = True
    proba, score = compiled.proba_and_score(rows)
    assert (proba[live] > 0.0).all()
    # float64 itself is only good to ~1e-5 nats here (|x - mu|^2 / sigma^2 ~ 4e9), on both paths
    np.testing.assert_allclose(proba[live], numpy_proba[live], rtol=1e-4)
    assert numpy_proba[proba == 0.0].max(initial=0.0) < 1e-30
    np.testing.assert_allclose(score, numpy_score, rtol=1e-12)
    proj, screen = compiled._screen_cache
    n_kept = np.concatenate([n for _, _, n in mppca_module._scored_chunks(rows, proj, screen, 128)])
    assert (n_kept >= live.sum(axis=1)).all() and (n_kept == 2).all()  # the far component is screened out
    compiled._screen_cache = (proj, screen._replace(gamma=0.0))
    assert (compiled.predict_proba(rows)[live] == 0.0).any()


@pytest.mark.parametrize("dataset", ["separated", "overlapping", "far"])
def test_screened_statistics_equal_the_numpy_paths(dataset):
    """The compiled E-step (``mppca_kernels.screened_moments``) against ``_accumulate``'s numpy path and against
    sums formed directly from the dense reference's responsibilities (those >= 1e-30): the same statistics to
    rounding, on well separated clusters (one component per row), overlapping ones (several live per row), and
    rows far from every component (most terms underflow), across chunk boundaries."""
    X = planted_mixture(16, [300, 300, 300])[0] if dataset == "separated" else overlapping_clusters(16)
    model = MPPCA(3, n_latent=2, max_iter=3, random_state=0).fit(X)
    if dataset == "far":
        X = np.concatenate([X, X[:60] * 40.0])
    proj = mppca_module._project(mppca_module._Params(*params(model)))
    numpy_stats = mppca_module._accumulate(X, proj, chunk_size=37)
    screened = mppca_module._accumulate(X, proj, 37, mppca_module._screen(proj))
    for name in numpy_stats._fields:
        np.testing.assert_allclose(getattr(screened, name), getattr(numpy_stats, name), rtol=1e-11, atol=1e-9)
    reference = dense_log_joint(X, *params(model))
    log_p = logsumexp(reference, axis=1)
    R = np.exp(reference - log_p[:, None])
    R[R < 1e-30] = 0.0
    shifted = X - proj.offset
    np.testing.assert_allclose(screened.counts, R.sum(axis=0), rtol=1e-9)
    np.testing.assert_allclose(screened.sums, R.T @ shifted, rtol=1e-9, atol=1e-9)
    sqdist = ((shifted[:, None, :] - proj.means[None]) ** 2).sum(axis=2)
    np.testing.assert_allclose(screened.sqdist, (R * sqdist).sum(axis=0), rtol=1e-9)
    np.testing.assert_allclose(screened.log_likelihood, log_p.sum(), rtol=1e-10)


def test_compiled_fit_follows_the_numpy_fit(monkeypatch):
    """``compiled=True`` fits on the screened E-step: the same EM (iterations, likelihoods, parameters to rounding
    carried through the iterations) as the numpy path, which ``VOXPOSE_KERNELS=numpy`` restores bit for bit."""
    X = overlapping_clusters(17, n_per=200)
    numpy_fit = MPPCA(4, n_latent=2, max_iter=15, tol=0.0, random_state=0).fit(X)
    compiled = MPPCA(4, n_latent=2, max_iter=15, tol=0.0, random_state=0, compiled=True).fit(X)
    assert compiled.n_iter_ == numpy_fit.n_iter_ == 15
    assert not np.array_equal(compiled.means_, numpy_fit.means_)  # the fit did take the compiled E-step
    np.testing.assert_allclose(compiled.log_likelihood_, numpy_fit.log_likelihood_, rtol=1e-10)
    for a, b in zip(params(compiled), params(numpy_fit), strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-9)
    monkeypatch.setenv("VOXPOSE_KERNELS", "numpy")
    fallback = MPPCA(4, n_latent=2, max_iter=15, tol=0.0, random_state=0, compiled=True).fit(X)
    for a, b in zip(params(fallback), params(numpy_fit), strict=True):
        np.testing.assert_array_equal(a, b)


def test_the_screen_groups_the_latent_columns_by_coordinate():
    """``mppca_kernels.screen_order``: the projection's stack has K mean columns, then component k's latent
    coordinate j at K + k q + j; the screen's float32 stack holds the means, then every component's coordinate 0,
    then every component's coordinate 1 (K = 3, q = 2 written out), with the float64 column norms alongside."""
    np.testing.assert_array_equal(mppca_kernels.screen_order(3, 2), [0, 1, 2, 3, 5, 7, 4, 6, 8])
    np.testing.assert_array_equal(mppca_kernels.screen_order(2, 0), [0, 1])
    model = MPPCA(3, n_latent=2, max_iter=3, random_state=0).fit(overlapping_clusters(2))
    proj = model._projection()
    screen = mppca_module._screen(proj)
    order = [0, 1, 2, 3, 5, 7, 4, 6, 8]
    np.testing.assert_array_equal(screen.stack32, proj.stack[:, order].astype(np.float32))
    np.testing.assert_allclose(screen.col_norm, np.linalg.norm(proj.stack[:, order], axis=0), rtol=1e-15)
    assert screen.stack_rows.shape[2] == mppca_kernels.padded_width(2) == 8
    for k in range(3):  # the exact evaluation's columns: component k's mean, its latent coordinates, then zeros
        np.testing.assert_array_equal(screen.stack_rows[k, :, :3], proj.stack[:, [k, 3 + 2 * k, 4 + 2 * k]])
        assert not screen.stack_rows[k, :, 3:].any()


@pytest.mark.parametrize("n_latent", [0, 5, 7, 9])
def test_exact_joint_sums_each_coordinate_in_column_order_bit_for_bit(n_latent):
    """``mppca_kernels._exact_joint`` keeps eight sums in local accumulators; each must still add ``x_i s_ij``
    over i = 0, 1, ... one term at a time from 0.0, as plain Python does, so the result is the same to the bit
    (q = 7 fills one block of eight exactly, q = 9 spills into a second), and the log joint follows from them."""
    rng = np.random.default_rng(n_latent)
    n_cols, n_components = 201, 3
    width = mppca_kernels.padded_width(n_latent)
    assert width % mppca_kernels.ACCUMULATORS == 0 and n_latent + 1 <= width < n_latent + 1 + 8
    x1 = rng.normal(size=(2, n_cols)) * np.exp(rng.normal(size=n_cols) * 3.0)  # wide range: order matters
    stack_rows = np.zeros((n_components, n_cols, width))
    stack_rows[:, :, : n_latent + 1] = rng.normal(size=(n_components, n_cols, n_latent + 1))
    noise, log_norm = np.array([0.5, 0.25, 2.0]), np.array([-3.0, -1.0, -2.0])
    sqnorm = float(np.sum(x1[1, :-1] ** 2))
    acc = np.empty(n_latent + 1)
    got = mppca_kernels._exact_joint(x1, 1, stack_rows, 2, sqnorm, noise, log_norm, n_latent, acc)
    want = []
    for j in range(n_latent + 1):
        total = 0.0
        for i in range(n_cols):
            total += float(x1[1, i]) * float(stack_rows[2, i, j])
        want.append(total)
    assert acc.tolist() == want
    latent = 0.0
    for value in want[1:]:
        latent += value * value
    assert got == ((sqnorm - want[0] * 2.0) - latent) / 2.0 * -0.5 + -2.0
