"""The workflow's steps on tiny generated data, run through the CLI as the rules run them: rig, motions, voxels,
descriptors, MPPCA, regression, evaluation and the model file (the predict, studio and heading tests' models)."""

import json

from voxpose.cli.main import main


def run(*args):
    assert main([str(a) for a in args]) == 0, args


def train_model(d, *, train, test, frames, rig, voxels, descriptor, features, regression, silhouettes=None,
                bvh_dir=None):
    """Everything under folder ``d``: ``rig.json``, ``<motion>.bvh/.h5``, ``vox_`` and ``desc_<motion>.h5``,
    ``features_model.h5``, ``features.h5``, ``regressor.h5``, ``baselines.h5``, ``fit.json``,
    ``predictions.h5``, ``angles.csv``, ``summary.json`` and ``model.h5``; the test motion's silhouettes as PNG
    folders in ``silhouettes`` when given. Motions are generated (``frames`` each), or with ``bvh_dir`` read from
    ``<bvh_dir>/<motion>.bvh`` (real motion capture, every frame)."""
    run("rig", "--params", json.dumps(rig), "-o", d / "rig.json")
    for name in (*train, test):
        if bvh_dir is None:
            kind, _, index = name.split("_")
            run("generate", "--kind", kind, "--index", int(index), "--frames", frames, "--seed", 5,
                "-o", d / f"{name}.bvh")  # fmt: skip
        source = d / f"{name}.bvh" if bvh_dir is None else bvh_dir / f"{name}.bvh"
        run("motion", source, "-o", d / f"{name}.h5")
        extra = ["--export-silhouettes", silhouettes] if name == test and silhouettes else []
        run("voxelize", d / f"{name}.h5", "--rig", d / "rig.json", "--params", json.dumps(voxels), "--seed", 7,
            "-o", d / f"vox_{name}.h5", *extra)  # fmt: skip
        run("describe", d / f"vox_{name}.h5", "--params", json.dumps(descriptor), "-o", d / f"desc_{name}.h5")
    run("fit-features", *(d / f"desc_{n}.h5" for n in train), "--method", "mppca", "--params", json.dumps(features),
        "--seed", 7, "-o", d / "features_model.h5")  # fmt: skip
    run("features", d / "features_model.h5", *(d / f"desc_{n}.h5" for n in (*train, test)), "-o", d / "features.h5")
    run("regress", d / "features.h5", *(d / f"{n}.h5" for n in train), "--train", ",".join(train),
        "--params", json.dumps(regression), "--seed", 7, "--regressor", d / "regressor.h5",
        "--baselines", d / "baselines.h5", "--fit", d / "fit.json")  # fmt: skip
    run("evaluate", d / "features.h5", d / f"{test}.h5", "--regressor", d / "regressor.h5", "--baselines",
        d / "baselines.h5", "--fit", d / "fit.json", "--test", test, "--params", json.dumps(regression),
        "--predictions", d / "predictions.h5", "--angles", d / "angles.csv", "-o", d / "summary.json")  # fmt: skip
    run("export-model", "--feature-model", d / "features_model.h5", "--regressor", d / "regressor.h5",
        "--summary", d / "summary.json", "--motions", *(d / f"{n}.h5" for n in train), "--voxels", json.dumps(voxels),
        "--descriptor", json.dumps(descriptor), "--regression", json.dumps(regression), "--seed", 7,
        "-o", d / "model.h5")  # fmt: skip
