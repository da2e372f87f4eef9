"""Dry runs of the workflow on folders of motion capture: CMU, Bandai and a fourth family mapped by one override
entry in one run, and a user's own folder that the shipped real-data settings (derived walks, experiments) do
not know."""

import json
import re
import shlex
import shutil

import pytest
import yaml

from tests.helpers import LAB_JOINT_MAP, copy_workflow, lab_family, snakemake
from voxpose.io.bvh import read_bvh, write_bvh
from voxpose.motion.generate import default_motion

pytestmark = pytest.mark.workflow  # slow: deselect with -m "not workflow"


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return copy_workflow(tmp_path_factory.mktemp("folders"))


def dry_run(workdir, config: dict):
    """A dry run (quick config plus ``config``) printing its shell commands; (stdout, stderr)."""
    path = workdir / "folders.yaml"
    path.write_text(yaml.safe_dump(config))
    proc = snakemake(workdir, "-n", "-p", configfiles=[path])
    return proc.stdout, proc.stderr


def commands(stdout: str, subcommand: str) -> list[str]:
    """The `voxpose <subcommand>` shell commands a dry run (``-p``) printed."""
    prefix = f"Shell command: voxpose {subcommand} "
    return [line.removeprefix("Shell command: ") for line in stdout.splitlines() if line.startswith(prefix)]


def motion_params(stdout: str) -> dict:
    """Motion name -> the settings its `voxpose motion` command is given."""
    out = {}
    for line in commands(stdout, "motion"):
        args = shlex.split(line)
        name = re.fullmatch(r"results/motions/(.+)\.h5", args[args.index("-o") + 1])[1]
        out[name] = json.loads(args[args.index("--params") + 1])
    return out


CMU = ["walk_cmu_02_01", "walk_cmu_08_01"]
BANDAI = ["walk_bandai1_walk_normal_001", "jog_bandai2_run_normal_001"]
LAB = {"walk_lab_07_01": "walk_cmu_07_01", "jog_lab_02_03": "jog_cmu_02_03"}  # renamed joints, other Euler orders


def test_one_run_mixes_cmu_bandai_and_a_family_mapped_by_one_override_entry(workdir, tmp_path, shared_bvh_dir):
    (tmp_path / "shared").mkdir()
    (tmp_path / "lab").mkdir()
    for name in CMU + BANDAI:
        shutil.copy(shared_bvh_dir / f"{name}.bvh", tmp_path / "shared")
    for name, source in LAB.items():
        write_bvh(lab_family(read_bvh(shared_bvh_dir / f"{source}.bvh")), tmp_path / "lab" / f"{name}.bvh")
    entry = {"files": ["*_lab_*"], "joint_map": LAB_JOINT_MAP}
    config = {"bvh_dir": [str(tmp_path / "shared"), str(tmp_path / "lab")], "motions": {"overrides": [entry]}}
    stdout, stderr = dry_run(workdir, config)
    params = motion_params(stdout)
    default = {"fps": 30.0, "unit_scale": None, "drop_reference_frame": "auto", "joint_map": None}
    assert {name: p for name, p in params.items() if "_lab_" in name} == {
        name: default | {"joint_map": LAB_JOINT_MAP} for name in LAB
    }
    others = {name: p for name, p in params.items() if "_lab_" not in name}
    assert set(CMU + BANDAI) | {"spiral_walk_cmu_08_01", "walk_cmu_02_01_turn090"} <= set(others)
    assert all(p == default for p in others.values())  # the presets detect CMU and Bandai themselves
    # the shipped table1 trains on the mapped family too (walk_*, jog_*) and tests on the derived spiral
    regress = commands(stdout, "regress")
    assert regress and all("walk_lab_07_01" in line and "jog_lab_02_03" in line for line in regress)
    # the shipped experiments that need the rest of the shared data are left out, one line each
    notes = [line for line in stderr.splitlines() if line.startswith("voxpose: ")]
    assert [n.split(":")[1].strip() for n in notes if "bvh_experiments" in n] == [
        "bvh_experiments.table2",
        "bvh_experiments.figure4",
        "bvh_experiments.broad",
    ]
    assert sum(n.startswith("voxpose: derived: skipped") for n in notes) == 1


def test_a_users_own_folder_runs_as_written(workdir, tmp_path):
    names = ["walk_mine_01", "walk_mine_02", "jog_mine_01"]
    for i, name in enumerate(names):
        write_bvh(default_motion(name.split("_")[0], i, n_frames=20, seed=1), tmp_path / f"{name}.bvh")
    stdout, stderr = dry_run(workdir, {"bvh_dir": str(tmp_path)})
    assert sorted(motion_params(stdout)) == sorted(names)  # every motion is loaded
    notes = [line for line in stderr.splitlines() if line.startswith("voxpose: ")]
    assert len(notes) == 6, notes  # the derived walks, each shipped experiment, the held-out groups: one line each
    assert notes[0].startswith("voxpose: derived: skipped 38 of 38 derived motions whose source is not in bvh_dir:")
    assert notes[5].startswith("voxpose: bvh_generalisation: skipped 9 groups with no motion")  # no CMU or Bandai file
    for note, name in zip(notes[1:5], ("table1", "table2", "figure4", "broad"), strict=True):
        assert note.startswith(f"voxpose: bvh_experiments.{name}: skipped, no training or no test motion")
    # the user's own experiment keeps the strict rules: a pattern that matches nothing is an error
    own = {"bvh_dir": str(tmp_path), "bvh_experiments": {"table1": {"train": ["walk_*"], "test": ["spiral_*"]}}}
    (workdir / "own.yaml").write_text(yaml.safe_dump(own))
    proc = snakemake(workdir, "-n", configfiles=[workdir / "own.yaml"], check=False)
    assert proc.returncode != 0
    assert "voxpose: error: config key bvh_experiments.table1.test: pattern 'spiral_*' matches no motion" in proc.stderr
