"""Reference regressors against closed forms and planted neighbours."""

import numpy as np
import pytest

from voxpose.errors import NotFittedError, VoxposeError
from voxpose.regression.baselines import KernelRidge, MeanPose, NearestNeighbour, cholesky_solve
from voxpose.regression.kernels import holdout_split


def data(n=60, d=3, p=2, seed=0):
    rng = np.random.default_rng(seed)
    x = rng.uniform(-1, 1, size=(n, d))
    y = np.stack([np.sin(2 * x[:, 0]) + x[:, 1], np.cos(x[:, 2])], axis=1)[:, :p]
    return x, y + 0.05 * rng.standard_normal((n, p))


def test_mean_pose():
    x, y = data()
    pred = MeanPose().fit(x, y).predict(x[:5])
    assert np.allclose(pred, y.mean(axis=0))
    assert MeanPose().fit(x, y[:, 0]).predict(x[:3]).shape == (3,)


def test_nearest_neighbour_picks_the_planted_row():
    x, y = data(n=50)
    rng = np.random.default_rng(1)
    rows = rng.choice(50, size=20)
    queries = x[rows] + 1e-4 * rng.standard_normal((20, 3))  # far closer to its row than to any other
    nn = NearestNeighbour(block=7).fit(x, y)
    assert np.array_equal(nn.neighbours(queries), rows)
    assert np.allclose(nn.predict(queries), y[rows])


def test_nearest_neighbour_ties_go_to_the_first_row():
    x = np.array([[0.0], [2.0], [2.0]])
    nn = NearestNeighbour().fit(x, np.array([0.0, 1.0, 2.0]))
    assert nn.neighbours(np.array([[1.0], [2.0]])).tolist() == [0, 1]


def test_kernel_ridge_equals_closed_form():
    x, y = data()
    width, ridge = 0.7, 0.05
    model = KernelRidge(kernel_width=width, ridge=ridge).fit(x, y)
    d2 = ((x[:, None, :] - x[None, :, :]) ** 2).sum(-1)
    k = np.exp(-d2 / (2 * width**2))
    a = np.linalg.solve(k + ridge * np.eye(len(x)), y - y.mean(axis=0))
    xt = np.linspace(-1, 1, 12).reshape(4, 3)
    kt = np.exp(-((xt[:, None, :] - x[None, :, :]) ** 2).sum(-1) / (2 * width**2))
    assert np.allclose(model.predict(xt), kt @ a + y.mean(axis=0))


def test_kernel_ridge_chooses_the_ridge_with_lowest_held_out_error():
    x, y = data(n=80, seed=2)
    ridges = (1e-6, 1e-2, 1.0, 100.0)
    model = KernelRidge(kernel_width=0.5, ridges=ridges, random_state=3).fit(x, y)
    fit_rows, val_rows = holdout_split(80, 0.2, random_state=3)
    errors = []
    for ridge in ridges:
        sub = KernelRidge(kernel_width=0.5, ridge=ridge).fit(x[fit_rows], y[fit_rows])
        errors.append(np.sqrt(np.mean(np.sum((sub.predict(x[val_rows]) - y[val_rows]) ** 2, axis=1))))
    assert model.ridge_ == ridges[int(np.argmin(errors))]
    assert np.allclose([e for _, e in model.validation_], errors)
    assert 1e-6 < model.ridge_ < 100.0  # neither interpolating the noise nor flattening the function


def test_kernel_ridge_groups_hold_out_whole_groups():
    x, y = data(n=60)
    groups = np.repeat(np.arange(6), 10)
    fit_rows, val_rows = holdout_split(60, 0.2, groups=groups, random_state=0)
    assert set(groups[fit_rows]).isdisjoint(groups[val_rows])
    assert KernelRidge(random_state=0).fit(x, y, groups=groups).ridge_ in KernelRidge().ridges


def test_kernel_ridge_ranks_ridges_on_max_rows_drawn_rows_and_refits_on_all():
    x, y = data(n=120, seed=4)
    groups = np.repeat(np.arange(12), 10)
    model = KernelRidge(kernel_width=0.5, max_rows=50, random_state=5).fit(x, y, groups=groups)
    # the documented draw: 50 rows at random, seeded, then the held-out split among them by whole groups
    drawn = np.sort(np.random.default_rng(5).choice(120, size=50, replace=False))
    alone = KernelRidge(kernel_width=0.5, random_state=5).fit(x[drawn], y[drawn], groups=groups[drawn])
    np.testing.assert_allclose([e for _, e in model.validation_], [e for _, e in alone.validation_], rtol=1e-10)
    assert [r for r, _ in model.validation_] == list(KernelRidge().ridges)
    assert model.ridge_ == alone.ridge_
    refit = KernelRidge(kernel_width=0.5, ridge=model.ridge_).fit(x, y)
    np.testing.assert_array_equal(model.dual_coef_, refit.dual_coef_)
    assert model.dual_coef_.shape == (120, 2)
    everything = KernelRidge(kernel_width=0.5, random_state=5).fit(x, y, groups=groups)
    assert KernelRidge(kernel_width=0.5, max_rows=120, random_state=5).fit(x, y, groups=groups).validation_ == (
        everything.validation_
    )
    assert everything.validation_ != model.validation_
    with pytest.raises(VoxposeError, match="kernel ridge: max_rows must be an integer >= 2"):
        KernelRidge(kernel_width=0.5, max_rows=1).fit(x, y)


def test_cholesky_solve_adds_jitter_to_singular_matrices():
    a = np.ones((3, 3))  # rank 1
    b = np.array([3.0, 3.0, 3.0])
    x = cholesky_solve(a, b)
    assert np.allclose(a @ x, b, atol=1e-4)
    with pytest.raises(VoxposeError, match="positive definite"):
        cholesky_solve(-np.eye(2), np.ones(2))


@pytest.mark.parametrize("model", [MeanPose(), NearestNeighbour(), KernelRidge(ridge=0.1)])
def test_bad_input_raises(model):
    x, y = data()
    with pytest.raises(NotFittedError, match=rf"^{type(model).__name__} is not fitted: call fit first$"):
        model.predict(x)
    with pytest.raises(VoxposeError, match="rows"):
        model.fit(x, y[:-1])
    with pytest.raises(VoxposeError, match="NaN"):
        model.fit(np.where(x > 0.9, np.nan, x), y)
    model.fit(x, y)
    with pytest.raises(VoxposeError, match="3 columns"):
        model.predict(x[:, :2])


def test_bad_ridge_and_width_raise():
    x, y = data()
    with pytest.raises(VoxposeError, match="ridge"):
        KernelRidge(ridge=-1.0).fit(x, y)
    with pytest.raises(VoxposeError, match="kernel width"):
        KernelRidge(kernel_width=0.0, ridge=1.0).fit(x, y)


@pytest.mark.parametrize("model", [MeanPose(), NearestNeighbour(block=7), KernelRidge(kernel_width=0.8)])
def test_a_baseline_restored_from_its_arrays_predicts_exactly_as_the_fitted_one(model):
    x, y = data()
    model.fit(x, y)
    restored = type(model).from_arrays(*model.to_arrays())
    queries = np.random.default_rng(3).uniform(-1, 1, size=(9, 3))
    np.testing.assert_array_equal(restored.predict(queries), model.predict(queries))


def test_an_unfitted_baseline_has_no_arrays():
    with pytest.raises(NotFittedError, match="NearestNeighbour is not fitted"):
        NearestNeighbour().to_arrays()


def test_kernel_ridge_constructor_is_keyword_only_after_the_kernel_width():
    assert KernelRidge(0.5).kernel_width == 0.5
    with pytest.raises(TypeError):
        KernelRidge(0.5, 0.1)


def test_cholesky_solve_gives_lapack_the_lower_factorisation_of_a_bit_for_bit_in_any_memory_order():
    import scipy.linalg

    rng = np.random.default_rng(4)
    f = rng.standard_normal((40, 50))
    a = f @ f.T  # symmetric bit for bit (numpy's symmetric rank-k product)
    b = rng.standard_normal((40, 3))
    shifted = np.asfortranarray(a + 0.25 * np.eye(40))
    reference = scipy.linalg.cho_solve(scipy.linalg.cho_factor(shifted, lower=True), b)
    for layout in (a, np.asfortranarray(a), a[::-1, ::-1][::-1, ::-1], a.tolist()):
        assert np.array_equal(cholesky_solve(layout, b, ridge=0.25), reference)


@pytest.mark.parametrize("rank", [40, 6])
def test_cholesky_solve_in_place_gives_the_copying_solve_bit_for_bit(rank):
    # rank 6 of 40 is singular: the in-place attempt fails, the matrix is restored and the jittered copies
    # then see the original; without the restore they would factor the failed attempt's leftovers
    rng = np.random.default_rng(5)
    f = rng.standard_normal((40, rank))
    a = f @ f.T
    b = rng.standard_normal((40, 2))
    expected = cholesky_solve(a, b, ridge=0.0 if rank == 6 else 0.1)
    consumed = a.copy()
    got = cholesky_solve(consumed, b, ridge=0.0 if rank == 6 else 0.1, overwrite_a=True)
    assert np.array_equal(got, expected)
    if rank == 40:
        assert not np.array_equal(consumed, a)  # factored in a itself, no copy
    else:
        assert np.array_equal(consumed, a)  # restored after the failed in-place attempt, copies after that


def test_cholesky_solve_with_a_ridge_solves_the_shifted_system_and_leaves_its_input_alone():
    rng = np.random.default_rng(2)
    f = rng.standard_normal((30, 6))
    a = f @ f.T  # rank 6 of 30: singular without the ridge
    b = rng.standard_normal((30, 3))
    before = a.copy()
    x = cholesky_solve(a, b, ridge=0.5)
    assert np.allclose(x, np.linalg.solve(a + 0.5 * np.eye(30), b), rtol=1e-10, atol=1e-12)
    assert np.array_equal(a, before)  # factored in a copy of its own
