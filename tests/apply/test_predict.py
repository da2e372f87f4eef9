"""``voxpose predict`` on new data: a small model trained through the workflow's own commands, applied to PNG
silhouettes of a held-out motion, gives the regression run's estimates and error; bad input fails cleanly."""

import json

import h5py
import numpy as np
import pandas as pd
import pytest

from tests.apply.pipeline import run, train_model
from tests.helpers import without_frame
from voxpose.apply.model_file import load_model
from voxpose.apply.outputs import read_record
from voxpose.apply.posed_body import skeleton_height
from voxpose.apply.root_fit import fit_roots
from voxpose.cli.main import main
from voxpose.descriptors.file import read_descriptors
from voxpose.evaluation import metrics
from voxpose.features.model import FeatureModel
from voxpose.features.novelty import frame_scores
from voxpose.io.bvh import read_bvh
from voxpose.io.hdf5 import read_per_motion
from voxpose.motion import canon
from voxpose.motion.load import load_motion
from voxpose.motion.output_skeleton import angles_from_bvh

# the tiny training's MPPCA stops at its max_iter of 10: expected, not a failure
pytestmark = pytest.mark.filterwarnings("ignore::voxpose.errors.ConvergenceWarning")

TRAIN = ("walk_gen_00", "jog_gen_00", "drunk_gen_00")
TEST = "walk_gen_01"
RIG = {"name": "six", "file": None, "n_cameras": 6, "radius": 4.0, "height": 2.0, "target_height": 1.0,
       "focal_px": 150.0, "width": 128, "image_height": 128}  # fmt: skip
VOXELS = {"l_res_fraction": 1 / 30, "min_views": None, "n_basis": 40, "follow_subject": True, "proportions": {}}
DESCRIPTOR = {"n_r": 3, "n_e": 3, "n_a": 6, "r_min": 1.0, "r_max": 1 / 3, "soft": True, "normalise": False}
FEATURES = {"n_components": 6, "n_latent": 2, "max_iter": 10, "tol": 1e-4, "fit_subsample": None,
            "kmeans_neighbours": 3}  # fmt: skip
# a kernel 3 x the median distance: on these 72 training frames it predicts the test walk better than 1 x (Eq. 6
# 9.2 against 10.2 deg) and varies smoothly with the hull, which tests/apply/test_studio.py needs (frame by frame
# within 1 deg of the workflow; at 1 x a few silhouette pixels move the angles by 1.2 deg)
REGRESSION = {"pca_variance": 0.9, "heading": "vector", "kernel_width": "auto", "width_scales": [3.0],
              "max_iter": 500, "tol": 1e-3}  # fmt: skip


def voxpose(capsys, *args):
    """Run ``voxpose`` in this process; -> (exit status, stderr)."""
    capsys.readouterr()
    status = main([str(a) for a in args])
    return status, capsys.readouterr().err


def one_line_error(result, *fragments):
    """Exit status 2 and one ``voxpose: error:`` line, the last one (progress lines may precede it)."""
    status, err = result
    lines = err.strip().splitlines()
    assert status == 2 and [line for line in lines if "error" in line] == lines[-1:], err
    assert lines[-1].startswith("voxpose: error: ")
    for fragment in fragments:
        assert fragment in lines[-1], lines[-1]


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """The workflow's steps on tiny data: motions, voxels, descriptors, MPPCA, regression, model file."""
    d = tmp_path_factory.mktemp("predict")
    train_model(d, train=TRAIN, test=TEST, frames=24, rig=RIG, voxels=VOXELS, descriptor=DESCRIPTOR,
                features=FEATURES, regression=REGRESSION, silhouettes=d / "sil")
    return d


def test_predict_from_png_silhouettes_reproduces_the_regression_run(trained):
    d = trained
    run("predict", d / "model.h5", "--rig", d / "rig.json", "--silhouettes", d / "sil", "-o", d / "out.bvh")
    workflow = read_per_motion(d / "predictions.h5", "predictions")[0][TEST]
    summary = json.loads((d / "summary.json").read_text())
    angles, root = angles_from_bvh(read_bvh(d / "out.bvh"))
    assert angles.shape == (24, canon.N_ANGLES) and workflow["valid"].all()
    np.testing.assert_allclose(angles, workflow["pred_mvrvm"], atol=1e-5)
    error = metrics.full_body_error(workflow["true"], angles)
    assert error == pytest.approx(summary["methods"]["mvrvm"]["full_body"], abs=1e-6)
    table = pd.read_csv(d / "out.csv")
    assert list(table.columns) == ["frame", "valid", *canon.ANGLE_NAMES] and table["valid"].all()
    np.testing.assert_allclose(table[list(canon.ANGLE_NAMES)].to_numpy(), workflow["pred_mvrvm"], atol=1e-5)
    # the position-based reader sees the same motion except the limbs' twist, which it cannot see
    reread = load_motion(d / "out.bvh")
    assert reread.source["skeleton"] == "generated" and reread.n_frames == 24
    assert metrics.full_body_error(workflow["true"], reread.angles) == pytest.approx(error, abs=1.0)


def _outputs_absent(directory, stem="out"):
    left = sorted(p.name for p in directory.iterdir() if p.name.startswith((stem, f".{stem}")))
    assert left == [], left


def test_predict_from_voxels_carries_truth_and_renders(trained, tmp_path):
    d = trained
    run("predict", d / "model.h5", "--voxels", d / f"vox_{TEST}.h5", "-o", tmp_path / "v.bvh")
    workflow = read_per_motion(d / "predictions.h5", "predictions")[0][TEST]
    prediction, skeleton, meta = read_record(tmp_path / "v.h5")
    np.testing.assert_allclose(prediction.angles, workflow["pred_mvrvm"], atol=1e-9)
    np.testing.assert_array_equal(prediction.true_angles, workflow["true"])
    assert prediction.fps == 30.0 and meta["source"] == {"voxels": str(d / f"vox_{TEST}.h5")}
    # the model's output skeleton scaled to the subject's measured height (tests/apply/test_root_fit.py)
    model = load_model(d / "model.h5")
    assert model.features.estimator.compiled  # predict's posteriors by the kernel, the workflow's by numpy: same angles
    model_skeleton = model.skeleton
    factor = prediction.voxels.h_sub / skeleton_height(model_skeleton)
    np.testing.assert_allclose(skeleton.offsets, model_skeleton.offsets * factor, rtol=1e-12)
    np.testing.assert_allclose(skeleton.end_lengths, model_skeleton.end_lengths * factor, rtol=1e-12)
    assert abs(factor - 1) > 0.01  # the test walk is not the training subjects' size
    # the root is the estimated body's fit to the hull (tests/apply/test_root_fit.py), in the record and the BVH
    fitted = fit_roots(prediction.voxels, prediction.angles, prediction.valid, skeleton)
    np.testing.assert_array_equal(prediction.root, fitted)
    np.testing.assert_allclose(angles_from_bvh(read_bvh(tmp_path / "v.bvh"))[1], fitted - prediction.voxels.shifts,
                               atol=1e-8)  # fmt: skip
    run("render", tmp_path / "v.h5", "--every", 6, "-o", tmp_path / "v.gif")
    from PIL import Image

    with Image.open(tmp_path / "v.gif") as gif:
        assert gif.n_frames == 4 and gif.format == "GIF"


def test_features_and_predict_say_how_far_the_input_lies_from_training(trained, tmp_path):
    d = trained
    motions, meta = read_per_motion(d / "features.h5", "features")
    model = FeatureModel.load(d / "features_model.h5")
    frames = read_descriptors(d / f"desc_{TEST}.h5")[0]
    np.testing.assert_allclose(motions[TEST]["novelty"], frame_scores(model.estimator, frames), rtol=1e-12)
    assert sorted(meta["novelty_by_motion"]) == sorted((*TRAIN, TEST))
    run("predict", d / "model.h5", "--voxels", d / f"vox_{TEST}.h5", "-o", tmp_path / "v.bvh")
    found, expected = read_record(tmp_path / "v.h5")[2]["novelty"], meta["novelty_by_motion"][TEST]
    assert found["warned"] == expected["warned"]
    np.testing.assert_allclose([found["median"], found["out_of_range"]], [expected["median"], expected["out_of_range"]])


def test_empty_hull_frames_are_gaps_not_estimates(trained, tmp_path):
    from voxpose.voxels.sequence import read_voxels, write_voxels

    d = trained
    seq, meta, angles = read_voxels(d / f"vox_{TEST}.h5")
    write_voxels(tmp_path / "gappy.h5", without_frame(without_frame(seq, 0), 5), meta, angles=angles)
    run("predict", d / "model.h5", "--voxels", tmp_path / "gappy.h5", "-o", tmp_path / "g.bvh")
    full = read_per_motion(d / "predictions.h5", "predictions")[0][TEST]["pred_mvrvm"]
    table = pd.read_csv(tmp_path / "g.csv")
    gaps = [0, 5]
    assert table.loc[gaps, "valid"].tolist() == [0, 0] and table.drop(index=gaps)["valid"].all()
    assert table.loc[gaps, list(canon.ANGLE_NAMES)].isna().all().all()
    kept = np.setdiff1d(np.arange(24), gaps)
    np.testing.assert_allclose(table.loc[kept, list(canon.ANGLE_NAMES)].to_numpy(), full[kept], atol=1e-5)
    bvh_angles, root = angles_from_bvh(read_bvh(tmp_path / "g.bvh"))
    assert (bvh_angles[gaps] == 0).all()  # the rest pose, not an estimate
    np.testing.assert_array_equal(root[0], root[1])  # a leading gap takes the first estimated frame's root
    np.testing.assert_array_equal(root[5], root[4])  # a later gap, the previous frame's


def test_rig_that_does_not_match_the_image_folders(trained, tmp_path, capsys):
    from voxpose.voxels.cameras import circular_rig, save_rig

    # a rig using a subset of the folders' cameras is fine; one with a camera the folders lack is not
    save_rig(circular_rig(n=7, width=128, image_height=128, focal_px=150.0, name="seven"), tmp_path / "seven.json")
    proc = voxpose(capsys, "predict", trained / "model.h5", "--rig", tmp_path / "seven.json", "--silhouettes",
                   trained / "sil", "-o", tmp_path / "out.bvh")  # fmt: skip
    one_line_error(proc, str(trained / "sil"), "no frames for camera(s) cam6 of rig seven")
    _outputs_absent(tmp_path)


def test_model_file_of_another_format_or_damaged(trained, tmp_path, capsys):
    other = tmp_path / "other.h5"
    other.write_bytes((trained / "model.h5").read_bytes())
    with h5py.File(other, "r+") as f:
        f.attrs["model_format"] = 2
    proc = voxpose(capsys, "predict", other, "--voxels", trained / f"vox_{TEST}.h5", "-o", tmp_path / "out.bvh")
    one_line_error(proc, str(other), "model file of format 2, this voxpose reads format 1")
    damaged = tmp_path / "damaged.h5"
    damaged.write_bytes((trained / "model.h5").read_bytes()[:3000])
    proc = voxpose(capsys, "predict", damaged, "--voxels", trained / f"vox_{TEST}.h5", "-o", tmp_path / "out.bvh")
    one_line_error(proc, str(damaged), "cannot read model file")
    proc = voxpose(capsys, "predict", trained / "features_model.h5", "--voxels", trained / f"vox_{TEST}.h5", "-o",
                   tmp_path / "out.bvh")  # fmt: skip
    one_line_error(proc, "expected a voxpose model file, found feature-model")
    _outputs_absent(tmp_path)


def test_files_that_are_not_images(trained, tmp_path, capsys):
    import shutil

    sil = tmp_path / "sil"
    shutil.copytree(trained / "sil", sil)
    bad = sorted((sil / "cam0").iterdir())[7]
    bad.write_text("not a PNG")
    proc = voxpose(capsys, "predict", trained / "model.h5", "--rig", trained / "rig.json", "--silhouettes", sil,
                   "-o", tmp_path / "out.bvh")  # fmt: skip
    one_line_error(proc, str(bad), "cannot read image")
    _outputs_absent(tmp_path)


def test_voxels_carved_at_another_resolution_are_refused(trained, tmp_path, capsys):
    other = dict(VOXELS, l_res_fraction=1 / 25)
    run("voxelize", trained / f"{TEST}.h5", "--rig", trained / "rig.json", "--params", json.dumps(other), "-o",
        tmp_path / "coarse.h5")  # fmt: skip
    proc = voxpose(
        capsys, "predict", trained / "model.h5", "--voxels", tmp_path / "coarse.h5", "-o", tmp_path / "out.bvh"
    )
    one_line_error(proc, str(tmp_path / "coarse.h5"), "the model needs 0.0333333")
    _outputs_absent(tmp_path)


def test_smoothing_keeps_straight_lines_and_respects_gaps_and_wraps():
    from voxpose.apply.predict import smooth_angles

    t = np.arange(60, dtype=float)
    angles = np.tile(t[:, None], (1, canon.N_ANGLES)) * 2.0
    angles[:, 0] = (100.0 + 3.0 * t + 180.0) % 360.0 - 180.0  # a heading that wraps at +-180
    angles[36:41] += np.where(np.arange(5) % 2, 4.0, -4.0)[:, None]  # jitter the smoothing must remove
    valid = np.ones(60, dtype=bool)
    valid[50] = False
    angles[50] = np.nan
    out = smooth_angles(angles, valid, 2.0)
    assert np.isnan(out[50]).all() and np.isfinite(np.delete(out, 50, axis=0)).all()
    line = 2.0 * t
    # the kernel reaches 8 frames (4 sigma): beyond that from the run's ends and the jitter, a line stays a line
    np.testing.assert_allclose(out[8:28, 1], line[8:28], atol=1e-9)
    assert np.abs(out[36:41, 1] - line[36:41]).max() < 0.5  # the +-4 degree jitter shrinks below 0.5
    np.testing.assert_allclose(out[51:, 1], smooth_angles(angles[51:], valid[51:], 2.0)[:, 1])  # runs apart
    heading = np.mod(out[8:28, 0] - (100.0 + 3.0 * t[8:28]) + 180.0, 360.0) - 180.0
    assert np.abs(heading).max() < 1e-9  # unwrapped before smoothing: the wrap near frame 27 does not smear
    np.testing.assert_array_equal(smooth_angles(angles, valid, 0.0), angles)
