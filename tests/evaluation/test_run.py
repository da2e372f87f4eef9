"""Training-frame thinning of an experiment's regression (voxpose.evaluation.run.thin_frames)."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.evaluation.run import thin_frames
from voxpose.regression import pose_encoding


def test_no_thinning_when_the_frames_fit():
    valid = [np.ones(30, bool), np.ones(20, bool)]
    assert thin_frames(valid, None) is valid
    assert thin_frames(valid, 50) is valid


def test_smallest_even_stride_that_fits_keeps_every_motion():
    valid = [np.ones(100, bool), np.ones(41, bool)]
    valid[0][[3, 4]] = False  # gaps are skipped, not counted
    kept = thin_frames(valid, 50)
    # brute force: stride 2 leaves 49 + 21 = 70 > 50, stride 3 leaves 33 + 14 = 47 <= 50
    assert [int(k.sum()) for k in kept] == [33, 14]
    assert np.array_equal(np.flatnonzero(kept[1]), np.arange(0, 41, 3))
    assert not (kept[0] & ~valid[0]).any()
    assert np.diff(np.flatnonzero(kept[0])[:3]).tolist() == [5, 3]  # 0, then 5 (3 and 4 are gaps), then 8


def test_cap_below_the_number_of_motions_is_refused():
    with pytest.raises(VoxposeError, match="max_train_frames"):
        thin_frames([np.ones(5, bool)] * 12, 10)


def _planted(tmp_path, kinds=("walk", "jog", "walk")):
    """Generated motions with features planted from their angles (sin, cos and noise): a regressor can learn them."""
    from voxpose.io.bvh import write_bvh
    from voxpose.motion.generate import generate_motion
    from voxpose.motion.load import load_motion

    motions, features = {}, {}
    rng = np.random.default_rng(0)
    for i, kind in enumerate(kinds):
        path = tmp_path / f"{kind}_gen_{i:02d}.bvh"
        write_bvh(generate_motion(kind, seed=i, n_frames=40, height=1.75), path)
        motion = load_motion(path)
        motions[motion.name] = motion
        angles = np.radians(motion.angles)
        planted = np.hstack([np.sin(angles), np.cos(angles)]) + 0.01 * rng.standard_normal((40, 84))
        counts = np.full(40, 200)
        counts[5] = 0  # a gap: no prediction, left out of the errors
        features[motion.name] = {"features": planted, "counts": counts}
    return motions, features


CFG = {"pca_variance": 0.9, "heading": "vector", "kernel_width": "auto", "width_scales": [0.8, 1.0],
       "max_iter": 40, "selection_max_iter": 3, "tol": 1e-3}  # fmt: skip


@pytest.mark.filterwarnings("ignore::voxpose.errors.ConvergenceWarning")  # the budgets are that small on purpose
def test_width_selection_fits_get_their_own_budget(tmp_path):
    """The candidate fits stop at ``selection_max_iter`` moves; the final fit keeps ``max_iter``."""
    from voxpose.evaluation.run import fit

    motions, features = _planted(tmp_path)
    names = sorted(motions)
    summary = fit(features, motions, names[:2], CFG, seed=0).summary
    assert [row["n_iter"] for row in summary["width_selection"]] == [3, 3]
    assert summary["mvrvm"]["n_iter"] > 3
    summary = fit(features, motions, names[:2], CFG | {"selection_max_iter": None}, seed=0).summary
    assert all(row["n_iter"] > 3 for row in summary["width_selection"])  # null: the candidates get max_iter too


@pytest.mark.filterwarnings("ignore::voxpose.errors.ConvergenceWarning")
def test_max_candidates_reaches_the_width_selection_and_the_final_fit(tmp_path):
    """78 training rows: 20 candidates (plus the chosen candidate fit's relevance vectors in the final fit);
    null keeps a Gaussian on every row."""
    from voxpose.evaluation.run import fit

    motions, features = _planted(tmp_path)
    names = sorted(motions)
    every = fit(features, motions, names[:2], CFG, seed=0).summary
    assert every["mvrvm"]["candidates"] == every["train_frames"] == 78
    summary = fit(features, motions, names[:2], CFG | {"max_candidates": 20}, seed=0).summary
    assert all(row["n_relevance"] <= 20 for row in summary["width_selection"])
    assert 20 <= summary["mvrvm"]["candidates"] <= 20 + max(row["n_relevance"] for row in summary["width_selection"])


@pytest.mark.filterwarnings("ignore::voxpose.errors.ConvergenceWarning")
def test_a_saved_fit_tests_exactly_as_the_fitted_one(tmp_path):
    """One fit serves every test set: saved and loaded, it gives the same predictions and errors, every method."""
    from voxpose.evaluation.run import Fit, fit

    motions, features = _planted(tmp_path, ("walk", "jog", "walk", "jog"))
    names = sorted(motions)
    fitted = fit(features, motions, names[:2], CFG, seed=0)
    fitted.save(tmp_path / "r.h5", tmp_path / "b.h5", tmp_path / "fit.json")
    loaded = Fit.load(tmp_path / "r.h5", tmp_path / "b.h5", tmp_path / "fit.json")
    for test in (names[2:3], names[2:]):
        pred_a, sum_a = fitted.test(features, motions, test)
        pred_b, sum_b = loaded.test(features, motions, test)
        assert sum_a == sum_b
        assert list(sum_a["methods"]) == ["mvrvm", "mean_pose", "nearest_neighbour", "kernel_ridge"]
        assert sum_a["test_frames"] == 39 * len(test) and sum_a["test_gaps"] == len(test)
        for name in test:
            for key in pred_a[name]:
                np.testing.assert_array_equal(pred_a[name][key], pred_b[name][key])
    # a regressor file alone (the claims, the model file): the MVRVM and the training mean pose
    alone = Fit.load(tmp_path / "r.h5", heading="vector")
    _, summary = alone.test(features, motions, names[2:3])
    assert list(summary["methods"]) == ["mvrvm", "mean_pose"]
    assert summary["methods"]["mvrvm"] == fitted.test(features, motions, names[2:3])[1]["methods"]["mvrvm"]


@pytest.mark.filterwarnings("ignore::voxpose.errors.ConvergenceWarning")
def test_kernel_ridge_chooses_its_ridge_on_held_out_training_motions(tmp_path):
    """The baseline's ridge table is the one of whole training motions held out (as for the MVRVM's width),
    recomputed here by direct solves; held-out random rows would give another table."""
    from voxpose.evaluation.run import _rows, fit
    from voxpose.regression.kernels import gaussian_kernel, holdout_split

    motions, features = _planted(tmp_path, ("walk", "jog", "walk", "jog"))
    names = sorted(motions)
    fitted = fit(features, motions, names, CFG, seed=0)
    ridge = fitted.baselines["kernel_ridge"]
    x, angles, groups = _rows(features, motions, names)
    z = fitted.pca.transform(pose_encoding.encode(angles, "vector"))
    gram = gaussian_kernel(x, x, ridge.kernel_width_)

    def table(fit_rows, val_rows):
        out = []
        for lam in ridge.ridges:
            mean = z[fit_rows].mean(axis=0)
            a = np.linalg.solve(gram[np.ix_(fit_rows, fit_rows)] + lam * np.eye(fit_rows.size), z[fit_rows] - mean)
            err = gram[np.ix_(val_rows, fit_rows)] @ a + mean - z[val_rows]
            out.append(np.sqrt(np.mean(np.sum(err * err, axis=1))))
        return np.array(out)

    fit_rows, val_rows = holdout_split(len(x), 0.2, groups, 0)
    assert not set(groups[val_rows]) & set(groups[fit_rows])  # whole motions held out
    found = np.array([rmse for _, rmse in ridge.validation_])
    np.testing.assert_allclose(found, table(fit_rows, val_rows), rtol=1e-6)
    assert not np.allclose(found, table(*holdout_split(len(x), 0.2, None, 0)), rtol=1e-3)
    # one training motion (a fixed width needs no held-out motion): the ridge is chosen on held-out rows
    alone = fit(features, motions, names[:1], CFG | {"kernel_width": 0.5}, seed=0).baselines["kernel_ridge"]
    assert len(alone.validation_) == len(alone.ridges)
