"""Every subcommand's parameters are checked at the edge (issue 21): a bad ``--params`` key or value, a bad
number, an output that cannot be a file or has the wrong format is one ``voxpose: error:`` line naming the
option, exit status 2, before any input is read and with nothing written: never a traceback, never a silent
default. The inputs named below do not exist: a check that ran after reading them would report them instead."""

import json

import pytest

from voxpose.cli.main import main

REGRESSION = {"pca_variance": 0.9, "heading": "vector", "kernel_width": "auto", "width_scales": [1.0],
              "max_iter": 500, "tol": 1e-3}  # fmt: skip
FEATURES = {"n_components": 6, "n_latent": 2, "max_iter": 10, "tol": 1e-4, "fit_subsample": None,
            "kmeans_neighbours": 3}  # fmt: skip


def _with(base: dict, **changes) -> str:
    return json.dumps(base | changes)


# (argv, fragments of the one error line); "OUT" is replaced by a path in the test's folder
CASES = {
    # the list
    "derive degrees not a number": (
        ["derive", "walk.bvh", "--kind", "turn", "--seed", "0", "--params", '{"degrees": "abc"}', "-o", "OUT.bvh"],
        ["--params key degrees: 'abc' is not a number"]),
    "derive unknown key": (
        ["derive", "walk.bvh", "--kind", "turn", "--seed", "0", "--params", '{"degrees": 90, "bogus": 1}',
         "-o", "OUT.bvh"], ["--params: unknown key 'bogus'"]),
    "derive spiral negative radius": (
        ["derive", "walk.bvh", "--kind", "spiral", "--seed", "0", "--params", '{"r_start": -1}', "-o", "OUT.bvh"],
        ["--params key r_start:"]),
    "describe unknown key": (["describe", "v.h5", "--params", '{"bogus": 1}', "-o", "OUT.h5"],
                             ["--params: unknown key 'bogus'"]),
    "render fps negative": (["render", "r.h5", "--fps", "-1", "-o", "OUT.gif"], ["--fps", "positive"]),
    "render fps zero": (["render", "r.h5", "--fps", "0", "-o", "OUT.gif"], ["--fps", "positive"]),
    "render every zero": (["render", "r.h5", "--every", "0", "-o", "OUT.gif"], ["--every", ">= 1"]),
    "predict fps zero": (["predict", "m.h5", "--voxels", "v.h5", "--fps", "0", "-o", "OUT.bvh"], ["--fps"]),
    "predict smooth nan": (["predict", "m.h5", "--voxels", "v.h5", "--smooth", "nan", "-o", "OUT.bvh"],
                           ["--smooth", "'nan' is not a finite number"]),
    "predict smooth negative": (["predict", "m.h5", "--voxels", "v.h5", "--smooth", "-1", "-o", "OUT.bvh"],
                                ["--smooth"]),
    "predict output not bvh": (["predict", "m.h5", "--voxels", "v.h5", "-o", "OUT.txt"], ["expected a .bvh file"]),
    "predict csv not csv": (["predict", "m.h5", "--voxels", "v.h5", "--csv", "OUT.txt", "-o", "OUT.bvh"],
                            ["--csv", "expected a .csv file"]),
    # the sweep: every --params and JSON option, numbers, seeds
    "motion fps text": (["motion", "w.bvh", "--params", '{"fps": "abc"}', "-o", "OUT.h5"], ["--params key fps:"]),
    "motion overrides": (["motion", "w.bvh", "--params", '{"overrides": []}', "-o", "OUT.h5"],
                         ["--params: unknown key 'overrides'"]),
    "motion reference frame": (["motion", "w.bvh", "--params", '{"drop_reference_frame": "yes"}', "-o", "OUT.h5"],
                               ["--params key drop_reference_frame:"]),
    "voxelize unknown key": (["voxelize", "m.h5", "--rig", "r.json", "--params", '{"l_res": 1}', "-o", "OUT.h5"],
                             ["--params: unknown key 'l_res'"]),
    "voxelize n_basis": (["voxelize", "m.h5", "--rig", "r.json", "--params", '{"n_basis": 0}', "-o", "OUT.h5"],
                         ["--params key n_basis:"]),
    "voxelize negative seed": (["voxelize", "m.h5", "--rig", "r.json", "--seed", "-3", "-o", "OUT.h5"], ["--seed"]),
    "degraded kind": (["voxelize-degraded", "m.h5", "--rig", "r.json", "--degradation", '{"kind": "zap", "level": 1}',
                       "-o", "OUT.h5"], ["--degradation key kind:"]),
    "degraded missing level": (["voxelize-degraded", "m.h5", "--rig", "r.json", "--degradation", '{"kind": "flip"}',
                                "-o", "OUT.h5"], ["--degradation: 'level' is a required property"]),
    "rig missing key": (["rig", "--params", '{"name": "x"}', "-o", "OUT.json"], ["--params: 'file' is a required"]),
    "describe n_r text": (["describe", "v.h5", "--params", '{"n_r": "four"}', "-o", "OUT.h5"], ["--params key n_r:"]),
    "fit-features tol": (["fit-features", "d.h5", "--method", "mppca", "--params", _with(FEATURES, tol=-1),
                          "-o", "OUT.h5"], ["--params key tol:"]),
    "fit-features kmeans without its votes": (
        ["fit-features", "d.h5", "--method", "kmeans", "--params",
         json.dumps({k: v for k, v in FEATURES.items() if k != "kmeans_neighbours"}), "-o", "OUT.h5"],
        ["--params: 'kmeans_neighbours' is a required property"]),
    "fit-features mppca without its latent size": (
        ["fit-features", "d.h5", "--method", "mppca", "--params",
         json.dumps({k: v for k, v in FEATURES.items() if k != "n_latent"}), "-o", "OUT.h5"],
        ["--params: 'n_latent' is a required property"]),
    "regress heading": (["regress", "f.h5", "m.h5", "--train", "m", "--params", _with(REGRESSION, heading="up"),
                         "--regressor", "OUT.h5", "--baselines", "OUT2.h5", "--fit", "OUT.json"],
                        ["--params key heading:"]),
    "evaluate unknown key": (["evaluate", "f.h5", "m.h5", "--regressor", "r.h5", "--test", "m", "--params",
                              _with(REGRESSION, bogus=1), "-o", "OUT.json"], ["--params: unknown key 'bogus'"]),
    "contexts unknown key": (["silhouette-contexts", "m.h5", "--rig", "r.json", "--params", '{"n_points": 100}',
                              "-o", "OUT.h5"], ["--params: 'n_r' is a required property"]),
    "contexts voxel params": (["silhouette-contexts", "m.h5", "--rig", "r.json", "--params",
                               json.dumps({"n_points": 100, "n_r": 5, "n_theta": 12, "r_inner": 0.1, "r_outer": 2}),
                               "--voxel-params", '{"follow": 1}', "-o", "OUT.h5"], ["--voxel-params: unknown key"]),
    "at cameras": (["fit-silhouette-features", "c.h5", "--params", json.dumps({"n_centres": 10, "neighbours": 3,
                    "fit_subsample": None, "max_iter": 5, "camera": 0}), "--cameras", "[-1]", "-o", "OUT.h5"],
                   ["--cameras"]),
    "at params": (["fit-silhouette-features", "c.h5", "--params", '{"n_centres": 1}', "--cameras", '"all"',
                   "-o", "OUT.h5"], ["--params"]),
    "export-model voxels": (["export-model", "--feature-model", "f.h5", "--regressor", "r.h5", "--summary", "s.json",
                             "--motions", "m.h5", "--voxels", '{"x": 1}', "--descriptor", "{}", "--regression",
                             json.dumps(REGRESSION), "--seed", "0", "-o", "OUT.h5"], ["--voxels: unknown key 'x'"]),
    "generate zero frames": (["generate", "--kind", "walk", "--index", "0", "--frames", "0", "--seed", "0",
                              "-o", "OUT.bvh"], ["--frames"]),
    "generate too many frames": (["generate", "--kind", "walk", "--index", "0", "--frames", "10000000000", "--seed",
                                  "0", "-o", "OUT.bvh"], ["--frames: 10000000000 is greater than the maximum of"]),
    "generate not bvh": (["generate", "--kind", "walk", "--index", "0", "--frames", "10", "--seed", "0",
                          "-o", "OUT.txt"], ["-o", "expected a .bvh file"]),
    "generate negative seed": (["generate", "--kind", "walk", "--index", "0", "--frames", "12", "--seed", "-1",
                                "-o", "OUT.bvh"], ["--seed"]),
    "carve zero basis": (["carve", "--rig", "r.json", "--silhouettes", "s", "--n-basis", "0", "-o", "OUT.h5"],
                         ["--n-basis"]),
    "carve nan size": (["carve", "--rig", "r.json", "--silhouettes", "s", "--l-res-fraction", "nan",
                        "-o", "OUT.h5"], ["--l-res-fraction"]),
    "gallery per kind": (["gallery", "p.h5", "v.h5", "--per-kind", "0", "-o", "OUT.png"], ["--per-kind"]),
    "threads zero": (["motion", "w.bvh", "--threads", "0", "-o", "OUT.h5"], ["--threads"]),
    "figure4 runs shape": (["figure4", "--runs", "{}", "--png", "OUT.png", "--pdf", "OUT.pdf", "--csv", "OUT.csv"],
                           ["--runs: {} is not of type 'array'"]),
    "generalisation runs shape": (["generalisation-table", "--runs", "[[1]]", "--csv", "OUT.csv", "--md", "OUT.md",
                                   "--png", "OUT.png"], ["--runs key 0:"]),
    "camera runs shape": (["camera-figure", "--runs", "[1]", "--png", "OUT.png", "--csv", "OUT.csv"],
                          ["--runs key 0: 1 is not of type 'object'"]),
    "robustness runs keys": (["robustness-figure", "--runs", '[{"kind": "flip"}]', "--png", "OUT.png", "--csv",
                              "OUT.csv"], ["--runs key 0: 'level' is a required property"]),
    "figure4 runs": (["figure4", "--runs", "[1", "--png", "OUT.png", "--pdf", "OUT.pdf", "--csv", "OUT.csv"],
                     ["--runs: not valid JSON"]),
    "camera runs": (["camera-figure", "--runs", "{", "--png", "OUT.png", "--csv", "OUT.csv"], ["--runs"]),
    "generalisation runs": (["generalisation-table", "--runs", "x", "--csv", "OUT.csv", "--md", "OUT.md",
                             "--png", "OUT.png"], ["--runs"]),
    "error-over-time pair": (["error-over-time", "--predictions", "p.h5", "-o", "OUT.png"],
                             ["--predictions 'p.h5': expected NAME=PATH"]),
    "joint-errors pair": (["joint-errors", "--summary", "s.json", "-o", "OUT.png"], ["--summary"]),
    "missing argument": (["motion"], ["motion: the following arguments are required"]),
    "no command": ([], ["voxpose: error: the following arguments are required: COMMAND"]),
    "unknown command": (["motions"], ["invalid choice: 'motions'"]),
}  # fmt: skip


def _one_line_error(status, err, fragments):
    lines = err.strip().splitlines()
    assert status == 2 and len(lines) == 1 and lines[0].startswith("voxpose: error: "), err
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


@pytest.mark.parametrize("name", list(CASES))
def test_a_bad_parameter_is_one_line_before_any_work(tmp_path, capsys, monkeypatch, name):
    argv, fragments = CASES[name]
    monkeypatch.chdir(tmp_path)
    argv = [a.replace("OUT", str(tmp_path / "out")) for a in argv]
    try:
        status = main(argv)
    except SystemExit as exit_:  # argparse
        status = exit_.code
    _one_line_error(status, capsys.readouterr().err, fragments)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("where", ["folder", "under a file"])
def test_an_output_that_cannot_be_a_file_is_named_before_any_work(tmp_path, capsys, where):
    (tmp_path / "folder").mkdir()
    (tmp_path / "file.h5").write_text("x")
    out = tmp_path / "folder" if where == "folder" else tmp_path / "file.h5" / "m.h5"
    status = main(["motion", str(tmp_path / "absent.bvh"), "-o", str(out)])
    _one_line_error(status, capsys.readouterr().err, [str(out), "folder"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file.h5", "folder"]


def test_a_number_like_string_in_params_is_the_number(tmp_path, capsys):
    """As in the config (voxpose.config_schema): ``"6e1"`` frames per second are 60."""
    from voxpose.cli.main import main as voxpose
    from voxpose.motion.data import read_motion

    bvh = tmp_path / "walk_gen_00.bvh"
    assert voxpose(["generate", "--kind", "walk", "--index", "0", "--frames", "12", "--seed", "0", "-o", str(bvh)]) == 0
    assert voxpose(["motion", str(bvh), "--params", '{"fps": "6e1"}', "-o", str(tmp_path / "m.h5")]) == 0
    assert read_motion(tmp_path / "m.h5").fps == 60.0


@pytest.mark.parametrize(
    "argv",
    [
        ["table1", "--ours", "IN", "IN", "--kmeans", "IN", "IN", "--csv", "OUT.csv", "--md", "OUT.md"],
        ["experiment-table", "--name", "x", "--test-set", "a", "IN", "IN", "--csv", "OUT.csv", "--md", "OUT.md"],
        ["joint-errors", "--summary", "a=IN", "-o", "OUT.png"],
        ["voxelize", "m.h5", "--rig", "IN", "-o", "OUT.h5"],
    ],
)
def test_a_binary_file_where_json_is_expected_is_named(tmp_path, capsys, monkeypatch, argv):
    """A summary or rig that is not text (an HDF5 file given by mistake) was a UnicodeDecodeError traceback."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "in.h5").write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(range(256)))
    argv = [a.replace("IN", str(tmp_path / "in.h5")).replace("OUT", str(tmp_path / "out")) for a in argv]
    if argv[0] == "voxelize":  # the motion must be read first: a real one
        bvh = tmp_path / "walk_gen_00.bvh"
        args = ["--kind", "walk", "--index", "0", "--frames", "12", "--seed", "0", "-o", str(bvh)]
        assert main(["generate", *args]) == 0
        assert main(["motion", str(bvh), "-o", str(tmp_path / "m.h5")]) == 0
        capsys.readouterr()
    status = main(argv)
    _one_line_error(status, capsys.readouterr().err, [str(tmp_path / "in.h5")])
    assert not any(p.name.startswith("out") for p in tmp_path.iterdir())
