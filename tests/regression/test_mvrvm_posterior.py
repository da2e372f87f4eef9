"""The MVRVM's incremental posterior against brute-force marginal likelihoods and posteriors."""

import numpy as np
import pytest

from tests.helpers import mvrvm_log_ml, mvrvm_toy
from voxpose.regression.design_statistics import DesignStatistics
from voxpose.regression.kernels import design_matrix
from voxpose.regression.mvrvm_alpha import contribution
from voxpose.regression.mvrvm_posterior import Posterior


def test_incremental_factors_match_brute_force():
    """S, Q and mu after adds, re-estimates and deletes equal their definitions via C_p (before and after
    the refresh that folds the rank-one terms), and the log ML changes by exactly the predicted gains."""
    x, y, _ = mvrvm_toy(n=40, seed=1)
    x[5] = x[4] + 1e-3  # rows 4 and 5 (basis functions 5 and 6) are near duplicates: aligned
    phi = design_matrix(x, x, 1.5, bias=True)
    beta = np.array([50.0, 200.0, 80.0])
    cap = np.full(3, 1e12)
    post = Posterior(DesignStatistics(x, x, 1.5, True, y), y, beta, alignment_max=0.999)
    lml, _ = post.refresh(update_beta=False, beta_cap=cap)
    moves = [("add", 0, 0.5), ("add", 11, 2.0), ("add", 30, 0.1), ("re", 11, 7.0), ("add", 5, 3.0)]
    moves += [("add", 21, 1.0), ("del", 0, None), ("re", 30, 0.02), ("del", 5, None), ("add", 6, 2.0)]
    moves += [("del", 21, None)]
    six_tracked = [True] * 4 + [False] * 4 + [True] * 3  # excluded while its duplicate 5 is active
    for (kind, j, alpha), tracked in zip(moves, six_tracked, strict=True):
        s, q = post.factors()
        current = 0.0 if kind == "add" else contribution(post.alpha[j], s[j], q[j] ** 2)
        new = 0.0 if kind == "del" else contribution(alpha, s[j], q[j] ** 2)
        {"add": post.add, "re": post.reestimate, "del": lambda j, _: post.delete(j)}[kind](j, alpha)
        lml += new - current
        assert post.tracked[6] == tracked
    act = post.active_basis
    assert sorted(act) == [6, 11, 30]
    assert lml == pytest.approx(mvrvm_log_ml(phi[:, act], y, post.alpha[act], post.beta), rel=1e-11)

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


def test_a_refresh_keeps_each_active_function_with_its_column_whether_or_not_slots_died():
    """Refresh moves the live slots to the front when some died (a deletion) and uses them in place otherwise:
    either way slot i holds the design column and Gram column of the function in slot i, and the log ML is
    the brute-force one."""
    x, y, _ = mvrvm_toy(n=30, seed=3)
    phi = design_matrix(x, x, 1.2, bias=True)
    cap = np.full(y.shape[1], 1e12)
    post = Posterior(DesignStatistics(x, x, 1.2, True, y), y, np.full(y.shape[1], 60.0), alignment_max=0.999)
    post.refresh(update_beta=False, beta_cap=cap)
    for j, alpha in ((3, 0.5), (17, 1.0), (8, 2.0), (25, 0.3)):
        post.add(j, alpha)
    for deleted in (True, False):
        if deleted:
            post.delete(17)  # slot 1 dies
        lml, _ = post.refresh(update_beta=False, beta_cap=cap)
        act = post.slot_basis[: post.n_slots]
        assert post.n_slots == post.k == (3 if deleted else 4)
        assert np.allclose(post.columns[:, : post.n_slots], phi[:, act], rtol=1e-12, atol=1e-15)
        assert np.array_equal(post.cross[:, : post.n_slots], post.design.gram[:, act])
        assert lml == pytest.approx(mvrvm_log_ml(phi[:, act], y, post.alpha[act], post.beta), rel=1e-11)
        post.add(12, 0.7)


def test_noise_update_keeps_the_best_of_old_mackay_and_em():
    x, y, _ = mvrvm_toy(n=60, seed=2)
    phi = design_matrix(x, x, 1.5, bias=True)
    cap = np.full(3, 1e12)
    post = Posterior(DesignStatistics(x, x, 1.5, True, y), y, np.array([1e4, 1.0, 3.0]), alignment_max=0.999)
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
        values = [mvrvm_log_ml(pa, y[:, [p]], alpha, np.array([b])) for b in options]
        assert post.beta[p] == pytest.approx(options[int(np.argmax(values))], rel=1e-9)
    assert after == pytest.approx(mvrvm_log_ml(pa, y, alpha, post.beta), rel=1e-10)


@pytest.mark.parametrize("bias", [True, False])
def test_alignment_counts_match_brute_force_cosines(bias):
    """A candidate is excluded while its cosine with an active basis function exceeds the limit: of the centred
    columns (means over the rows removed) when there is a bias column, else of the columns themselves. At a
    width twice the rows' spread every Gaussian is within an uncentred cosine of 0.999 of one of two active ones,
    but few are when centred."""
    x = np.linspace(-10.0, 10.0, 41)[:, None]
    y = np.stack([0.05 * x[:, 0], (x[:, 0] / 10) ** 2], axis=1)
    post = Posterior(DesignStatistics(x, x, 40.0, bias, y), y, np.array([100.0, 100.0]), alignment_max=0.999)
    post.refresh(update_beta=False, beta_cap=np.full(2, 1e12))
    active = [int(bias) + 3, int(bias) + 30]
    for j in active:
        post.add(j, 1.0)
    phi = design_matrix(x, x, 40.0, bias)
    columns = phi - phi.mean(axis=0) if bias else phi
    norms = np.linalg.norm(columns, axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        cosine = (columns.T @ columns[:, active]) / np.outer(norms, norms[active])
    expected = np.sum(cosine > 0.999, axis=1)
    np.testing.assert_array_equal(post.n_aligned, expected)
    # uncentred, every Gaussian is excluded; centred, only the 7 nearest the two active ones (3 and 30)
    assert np.count_nonzero(expected) == (7 if bias else 41)


def test_a_non_positive_variance_marks_the_posterior_degraded_until_a_refresh():
    x, y, _ = mvrvm_toy(n=40, seed=1)
    cap = np.full(3, 1e12)
    post = Posterior(DesignStatistics(x, x, 1.5, True, y), y, np.array([50.0, 200.0, 80.0]), alignment_max=0.999)
    post.refresh(update_beta=False, beta_cap=cap)
    for j, alpha in ((0, 0.5), (11, 2.0), (30, 0.1)):
        post.add(j, alpha)
    post.delete(11)  # a dead slot's variance is ~0 and does not count
    assert not post.degraded
    live = np.flatnonzero(post.live[: post.n_slots])
    post.diag[1, live[-1]] = -1e-9  # as accumulated rank-one round-off leaves it
    assert post.degraded
    post.refresh(update_beta=False, beta_cap=cap)
    assert not post.degraded
