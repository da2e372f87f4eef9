"""The ``voxpose`` command: user mistakes give one line and exit 2 with nothing left behind; stages chain."""

import os
import subprocess
import sys

import numpy as np
import pytest

from tests.helpers import one_line_error, run_voxpose
from voxpose.cli import main as cli
from voxpose.motion import canon
from voxpose.motion.data import read_motion
from voxpose.voxels.cameras import circular_rig, save_rig
from voxpose.voxels.sequence import read_voxels
from voxpose.voxels.silhouettes import write_silhouette_folder
from voxpose.voxels.voxelize import voxelize_motion


def test_malformed_bvh_names_file_and_line_and_leaves_nothing(tmp_path):
    bad = tmp_path / "walk_bad.bvh"
    bad.write_text(
        "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Xrotation Yrotation Zrotation\n"
        "  End Site\n  {\n    OFFSET 0 1 0\n  }\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n0 0 0\n0 zero 0\n"
    )
    out = tmp_path / "m.h5"
    proc = run_voxpose("motion", bad, "-o", out)
    one_line_error(proc, f"{bad}:15:")
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["walk_bad.bvh"]


def test_log_folder_is_made_and_an_unwritable_log_is_one_line(tmp_path):
    log = tmp_path / "logs" / "deep" / "rig.log"
    gen = ("generate", "--kind", "walk", "--index", "0", "--frames", "20", "--seed", "0", "-o")
    proc = run_voxpose(*gen, tmp_path / "walk.bvh", "--log", log)
    assert proc.returncode == 0, proc.stderr
    assert "walk.bvh" in log.read_text()
    blocker = tmp_path / "file"
    blocker.write_text("")
    proc = run_voxpose(*gen, tmp_path / "walk2.bvh", "--log", blocker / "x.log")
    one_line_error(proc, f"--log {blocker / 'x.log'}: cannot write it")
    assert not (tmp_path / "walk2.bvh").exists()


def test_bad_params_json_is_named():
    one_line_error(run_voxpose("motion", "x.bvh", "-o", "y.h5", "--params", "{fps: 30"), "--params")


@pytest.mark.parametrize(
    ("command", "key"),
    [("describe", '{"bogus": 1}'), ("voxelize", '{"l_res": 0.05}')],
)
def test_an_unknown_params_key_is_named_and_nothing_is_written(motion_file, tmp_path, command, key):
    source = motion_file if command == "voxelize" else tmp_path / "missing.h5"
    extra = ["--rig", tmp_path / "missing.json"] if command == "voxelize" else []
    proc = run_voxpose(command, source, *extra, "--params", key, "-o", tmp_path / "out.h5")
    one_line_error(proc, "--params: unknown key", key.split('"')[1])
    assert not (tmp_path / "out.h5").exists()


@pytest.fixture(scope="module")
def motion_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("cli")
    assert run_voxpose("generate", "--kind", "jog", "--index", "0", "--frames", "12", "--seed", "3", "-o",
                   d / "jog_gen_00.bvh").returncode == 0  # fmt: skip
    proc = run_voxpose("motion", d / "jog_gen_00.bvh", "-o", d / "jog_gen_00.h5", "--params", '{"fps": 30}')
    assert proc.returncode == 0, proc.stderr
    return d / "jog_gen_00.h5"


def test_generated_motion_loads_as_canonical_pose(motion_file):
    m = read_motion(motion_file)
    assert (m.name, m.kind, m.n_frames) == ("jog_gen_00", "jog", 12)
    assert m.angles.shape == (12, canon.N_ANGLES) and np.isfinite(m.angles).all()
    assert 1.5 <= m.height <= 2.0


def test_png_silhouettes_carve_like_the_direct_path(motion_file, tmp_path):
    rig = circular_rig(n=4, width=160, image_height=160, focal_px=190.0, name="four")
    save_rig(rig, tmp_path / "rig.json")
    motion = read_motion(motion_file)
    direct = voxelize_motion(motion, rig, n_basis=50, seed=1, keep_silhouettes=True)
    write_silhouette_folder(direct.silhouettes, rig, tmp_path / "sil")
    out = tmp_path / "carved.h5"
    proc = run_voxpose("carve", "--rig", tmp_path / "rig.json", "--silhouettes", tmp_path / "sil", "--n-basis", 50,
                   "--seed", 1, "-o", out)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    carved, meta, angles = read_voxels(out)
    assert angles is None and meta["rig"] == "four"
    assert carved.l_res == direct.l_res and carved.h_sub == direct.h_sub
    for key in ("ijk", "offsets", "surface", "basis", "basis_offsets", "empty"):
        assert np.array_equal(getattr(carved, key), getattr(direct, key)), key


def test_carve_with_a_rig_that_does_not_match_the_folders(motion_file, tmp_path):
    rig = circular_rig(n=4, width=160, image_height=160, focal_px=190.0, name="four")
    save_rig(rig, tmp_path / "rig.json")
    save_rig(circular_rig(n=6, width=160, image_height=160, focal_px=190.0), tmp_path / "rig6.json")
    seq = voxelize_motion(read_motion(motion_file), rig, n_basis=50, keep_silhouettes=True)
    write_silhouette_folder(seq.silhouettes[:2], rig, tmp_path / "sil")
    out = tmp_path / "carved.h5"
    proc = run_voxpose("carve", "--rig", tmp_path / "rig6.json", "--silhouettes", tmp_path / "sil", "-o", out)
    one_line_error(proc, "sil")
    assert not out.exists()


def test_voxelize_exports_png_silhouettes(motion_file, tmp_path):
    rig = circular_rig(n=3, width=96, image_height=96, focal_px=110.0, name="three")
    save_rig(rig, tmp_path / "rig.json")
    proc = run_voxpose("voxelize", motion_file, "--rig", tmp_path / "rig.json", "--params", '{"n_basis": 40}',
                   "--export-silhouettes", tmp_path / "png", "-o", tmp_path / "v.h5")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    seq, meta, angles = read_voxels(tmp_path / "v.h5")
    assert angles.shape == (12, canon.N_ANGLES) and meta["motion"] == "jog_gen_00"
    assert sorted(p.name for p in (tmp_path / "png").iterdir()) == ["cam0", "cam1", "cam2"]
    assert len(list((tmp_path / "png" / "cam0").glob("*.png"))) == 12


def test_describe_with_two_threads_equals_one_thread_and_the_reference(motion_file, tmp_path):
    from voxpose.descriptors.file import read_descriptors
    from voxpose.descriptors.shape_context import shape_contexts

    rig = circular_rig(n=3, width=96, image_height=96, focal_px=110.0, name="three")
    save_rig(rig, tmp_path / "rig.json")
    proc = run_voxpose("voxelize", motion_file, "--rig", tmp_path / "rig.json", "--params", '{"n_basis": 40}',
                   "-o", tmp_path / "v.h5")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    results = []
    for threads in (1, 2):
        out = tmp_path / f"d{threads}.h5"
        proc = run_voxpose("describe", tmp_path / "v.h5", "--params", '{"n_r": 3}', "--threads", threads, "-o", out)
        assert proc.returncode == 0, proc.stderr
        results.append(read_descriptors(out)[0])
    seq, _, _ = read_voxels(tmp_path / "v.h5")
    described = 0
    for f, (one, two) in enumerate(zip(*results, strict=True)):
        np.testing.assert_array_equal(one, two)
        if not seq.empty[f]:
            ijk, surface, basis = seq.frame(f)
            centres = (ijk + 0.5) * seq.l_res  # the direct definition on voxel centres, in metres
            ref = shape_contexts(centres[surface], centres[basis], l_res=seq.l_res, h_sub=seq.h_sub, n_r=3)
            np.testing.assert_allclose(one, ref, rtol=1e-6, atol=1e-9)  # stored as float32
            described += one.any()
    assert described == seq.n_frames


def test_threads_are_set_before_numpy_is_imported_and_only_the_command_is_imported(tmp_path):
    """BLAS reads its thread variables once, when numpy is imported: the CLI module imports neither numpy nor
    any subcommand, and ``main`` sets the variables from ``--threads`` before it imports the command's module."""
    script = (
        "import os, sys\n"
        "from voxpose.cli import main as cli\n"
        "assert 'numpy' not in sys.modules and 'voxpose.cli.regress' not in sys.modules\n"
        "status = cli.main(['check-config', 'missing.yaml', '--threads', '3'])\n"
        "print(status, os.environ['OMP_NUM_THREADS'], os.environ['OPENBLAS_NUM_THREADS'],\n"
        "      'voxpose.cli.check_config' in sys.modules, 'voxpose.cli.regress' in sys.modules)\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                                               "MKL_NUM_THREADS")}  # fmt: skip
    proc = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["2", "3", "3", "True", "False"]


def test_predicting_commands_import_neither_pandas_nor_scipy_linalg():
    """``voxpose evaluate`` (51 jobs of a default run, ~1 s each) loads a fitted MVRVM and its baselines and writes
    the predicted angles: it imports neither pandas (0.15 s) nor scipy.linalg (0.12 s); the code that fits imports
    scipy.linalg (the kernel ridge's Cholesky) and still not pandas (the width selection's table is plain records)."""
    script = (
        "import sys\n"
        "import voxpose.cli.evaluate, voxpose.evaluation.run, voxpose.evaluation.angles_csv\n"
        "print('pandas' in sys.modules, 'scipy.linalg' in sys.modules)\n"
        "from voxpose.regression import baselines, mvrvm\n"
        "import numpy as np\n"
        "baselines.cholesky_solve(np.eye(2), np.ones(2))\n"
        "x = np.random.default_rng(0).normal(size=(40, 2))\n"
        "mvrvm.select_kernel_width(x, x[:, 0], scales=(1.0,), random_state=0, max_iter=5)\n"
        "print('pandas' in sys.modules, 'scipy.linalg' in sys.modules)\n"
    )
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["False", "False", "False", "True"]


def test_a_user_error_reaches_stderr_in_one_write(monkeypatch, tmp_path):
    """Jobs running side by side share Snakemake's stderr. With unbuffered streams (PYTHONUNBUFFERED=1, as on
    our CI machines) ``print`` writes a line and its newline in two calls, and two jobs failing at once could
    interleave as ``voxpose: error: A`` ``voxpose: error: B`` ``\\n`` ``\\n``: neither line whole. The error line
    is one write (a pipe does not split writes below 4096 bytes)."""
    writes = []

    class Recorder:
        def write(self, text):
            writes.append(text)
            return len(text)

        def flush(self):
            pass

    monkeypatch.setattr(sys, "stderr", Recorder())
    assert cli.main(["check-config", "--base", str(tmp_path / "missing.yaml")]) == 2
    errors = [text for text in writes if "voxpose: error: " in text]
    assert len(errors) == 1 and errors[0].startswith("voxpose: error: ") and "missing.yaml" in errors[0]
    assert errors[0].count("\n") == 1 and "\n" not in writes
