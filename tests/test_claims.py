"""The measured claims (issue 8): rig files, claims config, A&T features, a stored regressor tested elsewhere."""


import numpy as np
import pytest

from tests.helpers import L_RES, ROOT, SPHERE, VOLUME_BOX, exact_hull, volume, walk_motion
from voxpose import workflow_config as wc
from voxpose.errors import VoxposeError
from voxpose.evaluation.run import Fit, evaluate
from voxpose.features.model import FeatureModel
from voxpose.features.silhouette import ContourSource, fit_codebook, render_contexts, silhouette_features
from voxpose.regression.mvrvm import MVRVM
from voxpose.regression.pose_space import PosePCA
from voxpose.voxels.cameras import circular_rig, load_rig
from voxpose.voxels.carve import Carver
from voxpose.voxels.render import render_silhouettes

CONTOUR = {"n_points": 40, "n_r": 5, "n_theta": 12, "r_inner": 0.125, "r_outer": 2.0}


def test_the_four_camera_rig_file_carves_the_sphere_within_its_visual_hull_bounds():
    rig = load_rig(ROOT / "config/rigs/circle4.json")
    assert len(rig) == 4 and np.allclose(rig.target, [0.0, 1.0, 0.0])
    ijk = set(map(tuple, Carver(rig, L_RES)(render_silhouettes(SPHERE, rig))))
    six = set(map(tuple, Carver(circular_rig(), L_RES)(render_silhouettes(SPHERE, circular_rig()))))
    exact = exact_hull(SPHERE, rig, L_RES, VOLUME_BOX)
    ratio = len(ijk) * L_RES**3 / volume(SPHERE)
    # from below the hull holds the sphere (3 % discretisation); from above, 4 horizontal orthographic views
    # give a square around every slice: 4 tan(pi / 4) / pi = 1.273 times the sphere, plus 1 %
    assert 0.97 <= ratio <= 4 / np.pi + 0.01
    assert abs(len(ijk) / len(exact) - 1.0) < 0.02
    assert len(six - ijk) < 0.02 * len(six)  # fewer views only add voxels (up to pixel sampling)
    assert len(ijk) > 1.05 * len(six)
    # every voxel whose centre lies inside the sphere, one voxel away from its surface (pixels are 0.7 cm), is kept
    grid = np.argwhere(np.ones((40, 40, 40), dtype=bool)) - 20 + np.array([0, 50, 0])
    inner = grid[np.linalg.norm((grid + 0.5) * L_RES - SPHERE.centres[0], axis=1) < 0.3 - L_RES]
    assert len(inner) > 10000 and set(map(tuple, inner)) <= ijk


def test_claims_rigs_and_degraded_sets_from_the_default_config():
    import yaml

    config = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    wc.validate_config(config)
    rigs = wc.claims_rigs(config["claims"], config["rig"])
    assert [wc.rig_camera_count(r) for r in rigs.values()] == [4, 8, 12, 6, 6]
    far = rigs["circle6.far"]  # derived from the default rig: tagged by both names
    assert far["name"] == "far" and far["radius"] == 6.0 and far["focal_px"] == config["rig"]["focal_px"]
    assert "irregular6" in rigs  # from a calibration file: its own name
    sets = wc.degraded_sets(config["claims"], "circle6", 6)
    levels = sum(len(v) for v in config["claims"]["degradations"].values())
    assert len(sets) == 2 * (levels + 1)
    assert sets["circle6__morph-2__min5"] == {"kind": "morph", "level": -2, "band_px": 2, "min_views": 5}
    assert sets["circle6__clean0__min6"]["kind"] == "none"


@pytest.mark.parametrize(
    "change",
    [
        {"rigs": [{"name": "circle6"}]},
        {"rigs": [{"name": "a__b"}]},
        {"rigs": [{"name": "x"}, {"name": "x"}]},
        {"retrain": ["nowhere"]},
    ],
)
def test_bad_claims_rigs_are_refused(change):
    claims = {"rigs": [{"name": "circle4", "n_cameras": 4}], "retrain": []} | change
    with pytest.raises(VoxposeError, match="config key claims"):
        wc.claims_rigs(claims, {"name": "circle6", "file": None, "n_cameras": 6})


def test_silhouette_features_per_view_and_refused_on_another_camera_count():
    motion = walk_motion(4)
    rig = circular_rig(n=3, focal_px=200.0, width=160, image_height=160)
    contexts, offsets = render_contexts(motion, rig, CONTOUR)
    assert len(offsets) == 4 * 3 + 1 and np.all(np.diff(offsets) == 40) and contexts.shape[1] == 60
    cfg = {"n_centres": 8, "neighbours": 2, "fit_subsample": None, "max_iter": 20}
    for cameras, width in (("all", 3 * 8), ([1], 8)):
        model = fit_codebook([ContourSource(offsets, 3, lambda: contexts)], cameras, cfg, seed=0)
        features, counts = silhouette_features(model, contexts, offsets, 3)
        assert features.shape == (4, width) and np.all(counts == 40 * width // 8)
        # each view's block is a soft histogram: it sums to one
        assert np.allclose(features.reshape(4, -1, 8).sum(axis=2), 1.0)
    single = features
    # the one-camera histogram is the one of camera 1's images alone
    alone = model.transform(contexts[offsets[1] : offsets[2]], np.zeros(40, dtype=int), 1)[0]
    assert np.allclose(single[0], alone[0])
    model = fit_codebook([ContourSource(offsets, 3, lambda: contexts)], "all", cfg, seed=0)
    with pytest.raises(VoxposeError, match="re-learnt"):
        silhouette_features(model, contexts[: offsets[8]], offsets[:9], 2)


def test_a_stored_regressor_predicts_what_the_fitted_one_does(tmp_path):
    from voxpose.io.hdf5 import write_arrays

    rng = np.random.default_rng(1)
    x = rng.normal(size=(30, 5))
    angles = np.zeros((30, 42))
    angles[:, 3:] = np.sin(x @ rng.normal(size=(5, 39)))
    pca = PosePCA(0.9).fit(angles[:, 1:])  # the "angle" heading encoding keeps 42 columns; vector adds one
    z = pca.transform(angles[:, 1:])
    model = MVRVM(kernel_width=2.0, random_state=0, max_iter=50).fit(x, z)
    write_arrays(tmp_path / "r.h5", "regressor", {"pca_mean": np.r_[0.0, pca.mean_],
                 "pca_components": np.c_[np.zeros(len(pca.components_)), pca.components_],
                 "relevance_vectors": model.relevance_vectors_, "coef": model.coef_, "relevance": model.relevance_,
                 "alpha": model.alpha_, "beta": model.beta_},
                 {"kernel_width": model.kernel_width_, "has_bias": model.has_bias_})  # fmt: skip
    predict = Fit.load(tmp_path / "r.h5", heading="angle").predictors()
    expected = pca.inverse_transform(model.predict(x[:7]))
    assert np.allclose(predict["mvrvm"](x[:7])[:, 1:], expected)
    assert np.allclose(predict["mean_pose"](x[:2])[:, 1:], pca.mean_)


def test_evaluate_counts_gaps_and_scores_each_method():
    import dataclasses

    motion = walk_motion(5)
    motion = dataclasses.replace(motion, angles=np.random.default_rng(0).uniform(-90, 90, size=(5, 42)))
    features = {motion.name: {"features": np.ones((5, 2)), "counts": np.array([3, 0, 3, 3, 3])}}
    truth = {"truth": lambda x: motion.angles[[0, 2, 3, 4]], "zero": lambda x: np.zeros((len(x), 42))}
    predictions, summary = evaluate(truth, features, {motion.name: motion}, [motion.name])
    assert summary["test_frames"] == 4 and summary["test_gaps"] == 1
    assert summary["methods"]["truth"]["full_body"] == pytest.approx(0.0, abs=1e-9)
    rms = np.sqrt((motion.angles[[0, 2, 3, 4]] ** 2).mean(axis=0)).mean()  # Eq. 6 against zero, by hand
    assert summary["methods"]["zero"]["full_body"] == pytest.approx(rms)
    assert np.isnan(predictions[motion.name]["pred_zero"][1]).all()


@pytest.mark.filterwarnings("ignore::voxpose.errors.ConvergenceWarning")  # a 10-iteration codebook on purpose
def test_feature_model_round_trip_keeps_the_cameras(tmp_path):
    rows = np.random.default_rng(0).normal(size=(200, 4))
    model = FeatureModel.fit("kmeans", rows, {"n_components": 5, "kmeans_neighbours": 2, "max_iter": 10}, 0)
    model.meta |= {"cameras": [0], "n_cameras": 4}
    model.save(tmp_path / "m.h5")
    assert FeatureModel.load(tmp_path / "m.h5").meta["cameras"] == [0]


@pytest.mark.parametrize("cameras", ["all", [2], [0, 2]])
def test_codebook_read_motion_by_motion_equals_the_fit_on_every_row(cameras):
    """fit_codebook draws its fit_subsample rows across motions as if they were concatenated and reads each
    motion once: the same codebook as a K-means fit on the concatenated rows of the chosen views."""
    rig = circular_rig(n=3, focal_px=200.0, width=160, image_height=160)
    sources, everything = [], []
    for height, frames in ((1.6, 3), (1.75, 5), (1.9, 2)):
        contexts, offsets = render_contexts(walk_motion(frames, height=height), rig, CONTOUR)
        sources.append(ContourSource(offsets, 3, lambda contexts=contexts: contexts))
        chosen = range(3) if cameras == "all" else cameras
        everything += [contexts[offsets[f * 3 + c] : offsets[f * 3 + c + 1]] for f in range(frames) for c in chosen]
    cfg = {"n_centres": 6, "neighbours": 2, "fit_subsample": 150, "max_iter": 20}
    model = fit_codebook(sources, cameras, cfg, seed=4)
    whole = np.concatenate(everything)
    expected = FeatureModel.fit("kmeans", whole, {"n_components": 6, "kmeans_neighbours": 2, "fit_subsample": 150,
                                                  "max_iter": 20}, 4)  # fmt: skip
    assert model.meta["n_train"] == len(whole) > 150 and model.meta["n_fit"] == 150
    for key, value in expected.to_arrays()[0].items():
        np.testing.assert_array_equal(model.to_arrays()[0][key], value, err_msg=key)
