"""Figure 6 of our own (issue 19): a generated studio as a lab brings it (``tests/studio.py``: OpenCV YAML in mm
with Z up and lens distortion, noisy images, a lighting change, a shadow) through the README's recipe
``rig import -> silhouettes -> carve -> predict``: the hull is the exact rig's, the angles the workflow's, and
carving while ignoring the distortion is measurably worse."""

import glob
import json
import shlex
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tests.apply.test_predict import DESCRIPTOR, REGRESSION, TEST, VOXELS, run, trained  # noqa: F401 (the fixture)
from tests.helpers import as_set
from tests.studio import FIRST_FRAME
from tests.studio import main as studio_main
from voxpose.evaluation import metrics
from voxpose.io.hdf5 import read_per_motion
from voxpose.motion import canon
from voxpose.voxels.cameras import load_rig
from voxpose.voxels.carve import Carver
from voxpose.voxels.sequence import read_voxels
from voxpose.voxels.silhouettes import iter_silhouette_folder

pytestmark = pytest.mark.filterwarnings("ignore::voxpose.errors.ConvergenceWarning")


def iou(a, b):
    a, b = as_set(a), as_set(b)
    return len(a & b) / len(a | b)


def readme_recipe() -> list:
    """The commands of the README's "Your own studio" block, continuation lines joined."""
    text = (Path(__file__).parents[2] / "README.md").read_text()
    block = text.split("## Your own studio", 1)[1].split("```bash\n", 1)[1].split("```", 1)[0]
    commands = block.replace("\\\n", " ").splitlines()
    return [shlex.split(line.split("  #")[0]) for line in commands if line.strip()]


def test_own_studio_recipe_matches_the_exact_rig_and_the_workflow(trained, tmp_path, monkeypatch):  # noqa: F811
    d = trained
    monkeypatch.chdir(tmp_path)
    studio = tmp_path / "studio"
    commands = readme_recipe()
    assert commands[0][:3] == ["python", "-m", "tests.studio"] and all(c[0] == "voxpose" for c in commands[1:])
    # the studio as the README writes it, with the motion the workflow predicted (walk_gen_01, not a new walk)
    studio_main([*commands[0][3:], "--motion", str(d / f"{TEST}.h5")])
    for command in commands[1:]:
        args = [a for arg in command[1:] for a in (sorted(glob.glob(arg)) if "*" in arg else [arg])]
        run(*[str(d / "model.h5") if a == "model.h5" else a for a in args])
    run("carve", "--rig", studio / "rig.json", "--silhouettes", studio / "sil", "--l-res-fraction",
        VOXELS["l_res_fraction"], "--n-basis", VOXELS["n_basis"], "-o", studio / "vox.h5")  # fmt: skip
    assert (studio / "preview.png").stat().st_size > 0 and (studio / "walk.gif").stat().st_size > 0
    run("predict", d / "model.h5", "--voxels", studio / "vox.h5", "-o", studio / "from_voxels.bvh")
    frames = pd.read_csv(studio / "from_voxels.csv")["frame"].tolist()  # the file names' numbers, not 0, 1, ...
    assert frames == list(range(FIRST_FRAME, FIRST_FRAME + len(frames)))

    # the hull: the imported rig and segmented silhouettes against the exact rig and exact silhouettes
    exact_rig, rig = load_rig(studio / "truth" / "rig.json"), load_rig(studio / "rig.json")
    seq, meta, _ = read_voxels(studio / "vox.h5")
    assert meta["frames"] == list(range(FIRST_FRAME, FIRST_FRAME + seq.n_frames))
    truth = list(iter_silhouette_folder(studio / "truth" / "silhouettes", exact_rig))
    found = list(iter_silhouette_folder(studio / "sil", rig))
    scores = {"with distortion": [], "distortion ignored": []}
    for label, carving_rig in (("with distortion", rig), ("distortion ignored", rig.without_distortion())):
        exact, carver = Carver(exact_rig, seq.l_res), Carver(carving_rig, seq.l_res)
        scores[label] = [iou(exact(t), carver(s)) for t, s in zip(truth, found, strict=True)]
    mean = {k: float(np.mean(v)) for k, v in scores.items()}
    print(f"studio hull IoU vs exact rig: with distortion {mean['with distortion']:.3f} "
          f"(min {min(scores['with distortion']):.3f}), distortion ignored {mean['distortion ignored']:.3f}")
    assert min(scores["with distortion"]) >= 0.9
    assert mean["distortion ignored"] < mean["with distortion"] - 0.05

    # the angles. The workflow's own predictions for this studio: its steps (voxelize -> describe -> features ->
    # evaluate) on the exact rig, lens included, with silhouettes it renders itself; the recipe's differ from them
    # only by the calibration files' round trip and the segmentation of noisy images.
    d_rig = tmp_path / "workflow"
    d_rig.mkdir()
    run("voxelize", d / f"{TEST}.h5", "--rig", studio / "truth" / "rig.json", "--params", json.dumps(VOXELS),
        "--seed", 7, "-o", d_rig / "vox.h5")  # fmt: skip
    run("describe", d_rig / "vox.h5", "--params", json.dumps(DESCRIPTOR), "-o", d_rig / f"desc_{TEST}.h5")
    run("features", d / "features_model.h5", d_rig / f"desc_{TEST}.h5", "-o", d_rig / "features.h5")
    run("evaluate", d_rig / "features.h5", d / f"{TEST}.h5", "--regressor", d / "regressor.h5", "--baselines",
        d / "baselines.h5", "--fit", d / "fit.json", "--test", TEST, "--params", json.dumps(REGRESSION),
        "--predictions", d_rig / "predictions.h5", "-o", d_rig / "summary.json")  # fmt: skip
    on_rig = read_per_motion(d_rig / "predictions.h5", "predictions")[0][TEST]
    pinhole = read_per_motion(d / "predictions.h5", "predictions")[0][TEST]
    table = pd.read_csv(studio / "walk.csv")
    assert table["frame"].tolist() == list(range(FIRST_FRAME, FIRST_FRAME + len(table)))
    angles = table[list(canon.ANGLE_NAMES)].to_numpy()
    between = metrics.frame_errors(on_rig["pred_mvrvm"], angles)  # Eq. 6 between the two, per frame
    ours, theirs = (metrics.full_body_error(on_rig["true"], a) for a in (angles, pinhole["pred_mvrvm"]))
    print(f"studio vs the workflow on the studio's rig: mean {between.mean():.3f} deg, frames up to "
          f"{between.max():.3f}; Eq. 6 error {ours:.3f} deg, the workflow's on the pinhole rig "
          f"{theirs:.3f} (frame by frame {metrics.full_body_error(pinhole['pred_mvrvm'], angles):.3f} deg from it)")
    assert between.mean() < 1.0
    # as accurate (Eq. 6) as the workflow's predictions with a pinhole rig: the lens costs nothing
    assert abs(ours - theirs) < 1.0
