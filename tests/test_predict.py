"""``voxpose predict`` on new data: a small model trained through the workflow's own commands, applied to PNG
silhouettes of a held-out motion, gives the regression run's estimates and error; bad input fails cleanly."""

import json
import subprocess
import sys

import h5py
import numpy as np
import pandas as pd
import pytest

from voxpose import canon, metrics
from voxpose.bvh import read_bvh
from voxpose.cli import main
from voxpose.model_file import load_model
from voxpose.motion_loader import load_motion
from voxpose.output_skeleton import angles_from_bvh
from voxpose.prediction_files import read_record
from voxpose.store import read_per_motion

TRAIN = ("walk_gen_00", "jog_gen_00", "drunk_gen_00")
TEST = "walk_gen_01"
RIG = {"name": "six", "file": None, "n_cameras": 6, "radius": 4.0, "height": 2.0, "target_height": 1.0,
       "focal_px": 150.0, "width": 128, "image_height": 128}  # fmt: skip
VOXELS = {"l_res_fraction": 1 / 30, "min_views": None, "n_basis": 40, "follow_subject": True, "proportions": {}}
DESCRIPTOR = {"n_r": 3, "n_e": 3, "n_a": 6, "r_min": 1.0, "r_max": 1 / 3, "soft": True, "normalise": False}
FEATURES = {"n_components": 6, "n_latent": 2, "max_iter": 20, "tol": 1e-4, "fit_subsample": None,
            "kmeans_neighbours": 3}  # fmt: skip
REGRESSION = {"pca_variance": 0.9, "heading": "vector", "kernel_width": "auto", "width_scales": [1.0],
              "max_iter": 500, "tol": 1e-3}  # fmt: skip


def run(*args):
    assert main([str(a) for a in args]) == 0, args


def voxpose(*args):
    return subprocess.run([sys.executable, "-m", "voxpose", *map(str, args)], capture_output=True, text=True)


def one_line_error(proc, *fragments):
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("voxpose: error: "), proc.stderr
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """The workflow's steps on tiny data: motions, voxels, descriptors, MPPCA, regression, model file."""
    d = tmp_path_factory.mktemp("predict")
    run("rig", "--params", json.dumps(RIG), "-o", d / "rig.json")
    for name in (*TRAIN, TEST):
        kind, _, index = name.split("_")
        run("generate", "--kind", kind, "--index", int(index), "--frames", 24, "--seed", 5, "-o", d / f"{name}.bvh")
        run("motion", d / f"{name}.bvh", "-o", d / f"{name}.h5")
        extra = ["--export-silhouettes", d / "sil"] if name == TEST else []
        run("voxelize", d / f"{name}.h5", "--rig", d / "rig.json", "--params", json.dumps(VOXELS), "--seed", 7,
            "-o", d / f"vox_{name}.h5", *extra)  # fmt: skip
        run("describe", d / f"vox_{name}.h5", "--params", json.dumps(DESCRIPTOR), "-o", d / f"desc_{name}.h5")
    run("fit-features", *(d / f"desc_{n}.h5" for n in TRAIN), "--method", "mppca", "--params", json.dumps(FEATURES),
        "--seed", 7, "-o", d / "features_model.h5")  # fmt: skip
    run("features", d / "features_model.h5", *(d / f"desc_{n}.h5" for n in (*TRAIN, TEST)), "-o", d / "features.h5")
    run("regress", d / "features.h5", *(d / f"{n}.h5" for n in (*TRAIN, TEST)), "--train", ",".join(TRAIN),
        "--test", TEST, "--params", json.dumps(REGRESSION), "--seed", 7, "--model", d / "regressor.h5",
        "--predictions", d / "predictions.h5", "--angles", d / "angles.csv", "--summary", d / "summary.json")  # fmt: skip
    run("export-model", "--feature-model", d / "features_model.h5", "--regressor", d / "regressor.h5",
        "--summary", d / "summary.json", "--motions", *(d / f"{n}.h5" for n in TRAIN), "--voxels", json.dumps(VOXELS),
        "--descriptor", json.dumps(DESCRIPTOR), "--regression", json.dumps(REGRESSION), "--seed", 7,
        "-o", d / "model.h5")  # fmt: skip
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
