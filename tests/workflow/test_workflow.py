"""End to end: the quick configuration through Snakemake, cached partial reruns, determinism, config errors.

The workflow runs once per test session in a temporary copy of the repository (``conftest.quick_run``: ``python -m
snakemake`` as a subprocess); tests here restore what they edit in it, and later tests ask dry runs which rules a
change would schedule.
"""

import csv
import json
import os
import re
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest
import yaml
from snakemake.utils import update_config

from tests.helpers import ROOT, run_voxpose, scheduled, snakemake
from voxpose import workflow_config as wc
from voxpose.evaluation import readme_tables
from voxpose.provenance import NOT_GIT, config_hash

pytestmark = pytest.mark.workflow  # slow: deselect with -m "not workflow"


def test_the_quick_run_went_through_the_job_server(quick_run):
    """Its jobs ran in forks of the job server (voxpose.cli.job_server), none refused, and the tables they made
    equal the reference run's (``test_quick_tables_equal_the_reference_run``). A job that starts before the
    server listens runs alone: a few at most."""
    log = (quick_run / "results/logs/job_server.log").read_text()
    jobs = [p for p in (quick_run / "results/logs").rglob("*.log") if p.name != "job_server.log"]
    served = log.count(": exit 0 after ")
    assert "refused" not in log
    assert len(jobs) - 10 <= served <= len(jobs)


def test_quick_run_writes_every_artifact(quick_run):
    for name in (
        "tables/table1.csv",
        "tables/table1.md",
        "tables/table2.csv",
        "tables/table2.md",
        "tables/figure4.csv",
        "figures/figure4.png",
        "figures/figure4.pdf",
        "figures/gallery.png",
        "figures/joint_errors.png",
        "figures/error_over_time.png",
        "models/table1/circle6-quick/R0.3333-r2-4x5x10-soft-body/mppca-K16-q3/model.h5",
        "models/table2/circle6-quick/R0.3333-r2-4x5x10-soft-body/mppca-K16-q3/model.h5",
        "figures/camera_rigs.png",
        "tables/camera_rigs.csv",
        "figures/robustness.png",
        "tables/robustness.csv",
    ):
        assert (quick_run / "results" / name).stat().st_size > 0, name
    t1 = pd.read_csv(quick_run / "results/tables/table1.csv")
    ours = t1[(t1["source"] == "voxpose (measured)")].iloc[0]
    assert 0 < ours["full body"] < 60 and 0 < ours["mean-pose baseline (full body)"] < 60
    assert ours["test frames"] == 40  # spiral_gen_01, every frame carved
    paper = t1[t1["source"] == "paper"].iloc[0]
    assert (paper["full body"], paper["body heading angle"]) == (5.2, 8.8)
    train, test = ([f"{k}_gen_{i}" for k in ("drunk", "jog", "jump", "spiral", "walk")] for i in ("00", "01"))
    run = f"results/runs/{wc.motion_set_tag(train)}/circle6-quick/R0.3333-r2-4x5x10-soft-body/mppca-K16-q3"
    summary = json.loads((quick_run / run / f"sets/{wc.motion_set_tag(test)}/summary.json").read_text())
    assert summary["train"] == [f"{k}_gen_00" for k in ("drunk", "jog", "jump", "spiral", "walk")]
    assert set(summary["methods"]) == {"mvrvm", "mean_pose", "nearest_neighbour", "kernel_ridge"}
    assert all(v["per_kind"].keys() == {"drunk", "jog", "jump", "spiral", "walk"} for v in summary["methods"].values())
    t2 = pd.read_csv(quick_run / "results/tables/table2.csv")
    measured = t2[t2["source"] == "voxpose (measured)"].iloc[0]
    for col in ("regular walking", "drunken walking", "spiral walking", "jogging", "jump"):
        assert 0 < measured[col] < 60
    assert 0 < measured["relevance vectors"] < measured["training frames"]


def test_report_pages_show_the_paper_beside_ours(quick_run):
    tables = quick_run / "results/tables"
    page = (tables / "table1.html").read_text()
    assert "<table>" in page and ">5.2<" in page and "difference (voxpose - paper)" in page and "varying angles" in page
    assert ">2.5<" in (tables / "table2.html").read_text()
    claims = pd.read_csv(tables / "claims.csv")
    assert set(claims["verdict"]) <= {"held", "reversed", "not shown"} and len(claims) >= 8  # 2 + 2 + 5 types
    summary = (quick_run / "results/report/summary.html").read_text()
    for text in ("Table 1", "Table 2", "Figure 4", "configuration hash", "numpy", "data:image/png;base64", ">5.2<"):
        assert text in summary, text


def test_readme_tables_have_the_format_a_fresh_run_generates(quick_run):
    """The README's generated block equals ``voxpose readme-tables`` on this quick run, every number aside."""
    readme = readme_tables.block((ROOT / "README.md").read_text()).split("\n\n")
    fresh = readme_tables.markdown(quick_run / "results/tables").split("\n\n")
    assert len(readme) == len(fresh)
    for i, (ours, theirs) in enumerate(zip(readme, fresh, strict=True)):
        if i and readme[i - 1].startswith(("**Claims:", "**Generalisation")):  # rows named after the config's
            # rigs or held-out groups: header only
            ours, theirs = (t.splitlines()[0] for t in (ours, theirs))
        verdict = re.compile(r"\| (held|reversed|not shown) \|$", re.M)  # a claim's verdict differs by run
        ours, theirs = (verdict.sub("| VERDICT |", t) for t in (ours, theirs))
        assert readme_tables.normalised(ours) == readme_tables.normalised(theirs)


def test_claims_artifacts(quick_run):
    t1 = pd.read_csv(quick_run / "results/tables/table1.csv")
    at = t1[t1["method"].str.startswith("Agarwal & Triggs-style")]
    assert len(at) == 2 and (at["source"] == "voxpose (measured)").all() and (at["test frames"] == 40).all()
    rigs = pd.read_csv(quick_run / "results/tables/camera_rigs.csv").set_index(["rig", "series"])["error (deg)"]
    # the stored regressor applied to the default rig's test features reproduces the run that trained it
    assert rigs[("circle6-quick", "trained on circle6-quick, not retrained (voxels)")] == pytest.approx(
        rigs[("circle6-quick", "retrained on this rig (voxels)")]
    )
    # the multi-view A&T features do not exist on a rig with another number of cameras
    assert np.isnan(rigs[("circle4-quick", "A&T, 6 views concatenated, trained on circle6-quick")])
    robust = pd.read_csv(quick_run / "results/tables/robustness.csv")
    assert set(robust["kind"]) == {"flip", "morph", "limb", "calibration"}
    assert robust["error (deg)"].between(0, 60).all()


def test_nothing_changed_reruns_nothing(quick_run):
    assert scheduled(quick_run) == {}


def _override(quick_run, name, text):
    path = quick_run / f"{name}.yaml"
    path.write_text(text)
    return path


def test_changing_k_reruns_only_features_onward(quick_run):
    jobs = scheduled(quick_run, _override(quick_run, "k", "features:\n  n_components: 12\n"))
    assert {"fit_features", "features", "regress", "table1", "table2"} <= set(jobs)
    assert not {"generate_bvh", "motion", "rig", "voxelize", "describe"} & set(jobs)


def test_changing_r_max_reruns_descriptors_onward_not_carving(quick_run):
    jobs = scheduled(quick_run, _override(quick_run, "r", "descriptor:\n  r_max: 0.3\n"))
    assert {"describe", "fit_features", "features", "regress", "table1"} <= set(jobs)
    assert not {"generate_bvh", "motion", "rig", "voxelize"} & set(jobs)


def test_an_override_entry_reruns_only_the_motions_it_matches(quick_run):
    entry = "motions:\n  overrides:\n    - files: ['walk_gen_00']\n      fps: 25.0\n"
    jobs = scheduled(quick_run, _override(quick_run, "motion_entry", entry))
    assert jobs["motion"] == 1 and {"voxelize", "describe", "regress"} <= set(jobs)
    assert "generate_bvh" not in jobs
    # the shipped entry (ReActIdle files) matches no generated motion: without it nothing changes
    assert scheduled(quick_run, _override(quick_run, "no_entries", "motions:\n  overrides: []\n")) == {}


def test_a_changed_rig_under_a_new_name_reruns_from_carving(quick_run):
    jobs = scheduled(quick_run, _override(quick_run, "rig", "rig:\n  name: far\n  radius: 4.5\n"))
    assert {"rig", "voxelize", "describe", "fit_features", "regress", "table1"} <= set(jobs)
    assert not {"generate_bvh", "motion"} & set(jobs)


def test_a_changed_rig_that_keeps_its_name_is_refused(quick_run):
    # its results would land in the old rig's folders (rig.n_cameras: 8 under circle6)
    bad = _override(quick_run, "rig_same_name", "rig:\n  n_cameras: 8\n")
    proc = snakemake(quick_run, "-n", configfiles=[bad], check=False)
    assert proc.returncode != 0
    assert "voxpose: error: config key rig: the rig named 'circle6-quick' differs from the one in" in proc.stderr


def _rules_and_commands() -> dict:
    """Rule name -> the `voxpose` subcommand its shell runs and the subcommand its code hash names."""
    out = {}
    for path in (ROOT / "workflow/rules").glob("*.smk"):
        for block in re.split(r"(?m)^(?=rule \w+:)", path.read_text())[1:]:
            name = re.match(r"rule (\w+):", block)[1]
            shell = re.search(r'"voxpose ([a-z0-9-]+)', block)
            code = re.search(r'code=code\("([a-z0-9-]+)"\)', block)
            out[name] = (shell and shell[1], code and code[1])
    return out


def test_every_rule_hashes_the_code_of_the_command_it_runs():
    rules = _rules_and_commands()
    assert rules, "no rules found"
    for name, (shell, code) in rules.items():
        if name != "all":
            assert shell is not None and code == shell, name


def _rules_reaching(workdir, module: str) -> list[str]:
    """Rules whose command's import closure contains ``module`` (computed on the package copy in ``workdir``)."""
    from voxpose.cli.main import SUBCOMMANDS
    from voxpose.import_graph import closure, import_graph

    graph = import_graph(workdir / "voxpose")
    return sorted(name for name, (shell, _) in _rules_and_commands().items()
                  if shell and module in closure(SUBCOMMANDS[shell].module, graph))  # fmt: skip


def _edited(workdir, module: str):
    """Append a comment to ``module`` of the package copy; return a function that restores it."""
    path = workdir / (module.replace(".", "/") + ".py")
    text = path.read_text()
    path.write_text(text + "\n# edited by a test\n")
    return lambda: path.write_text(text)


@pytest.mark.parametrize(
    "module",
    [
        "voxpose.descriptors.contour",  # reached by the A&T rules only through voxpose.features.silhouette
        "voxpose.voxels.surface",  # reached by the carving rules through voxpose.voxels.voxelize
    ],
)
def test_editing_a_module_reruns_the_rules_that_reach_it_and_their_dependants_only(quick_run, module):
    reaching = _rules_reaching(quick_run, module)
    assert reaching  # the module is used indirectly by some rule of the DAG
    expected = scheduled(quick_run, args=("--forcerun", *reaching))
    restore = _edited(quick_run, module)
    try:
        assert scheduled(quick_run) == expected
    finally:
        restore()
    assert scheduled(quick_run) == {}


def test_editing_a_module_no_rule_reaches_reruns_nothing(quick_run):
    assert _rules_reaching(quick_run, "voxpose.apply.animation") == []  # `voxpose render`, not in the DAG
    restore = _edited(quick_run, "voxpose.apply.animation")
    try:
        assert scheduled(quick_run) == {}
    finally:
        restore()


def test_an_override_with_every_key_at_its_current_value_schedules_nothing(quick_run):
    # every section reversed: a --configfile merge reorders keys, which must not read as a change
    config = yaml.safe_load((quick_run / "config/config.yaml").read_text())
    for key, value in yaml.safe_load((quick_run / "config/quick.yaml").read_text()).items():
        config[key] = value if not isinstance(value, dict) else config[key] | value

    def reverse(value):
        return {k: reverse(value[k]) for k in reversed(value)} if isinstance(value, dict) else value

    same = _override(quick_run, "same", yaml.safe_dump(reverse(config), sort_keys=False))
    assert scheduled(quick_run, same) == {}


# The artifacts at fixed paths (results/tables/table1.csv, ...) show the current config's results: they are
# rebuilt from cached results (seconds each) when the config changes, and on the way back.
ARTIFACT_RULES = {"table1", "table2", "figure4", "gallery", "joint_errors", "error_over_time", "camera_figure",
                  "robustness_figure", "experiment_table", "generalisation_table", "paper_claims", "report_summary",
                  "all"}  # fmt: skip


NAMED_SETS = """experiments:
  heldout:                      # the training set of table2: its fits are shared
    train: ["*_gen_00"]
    test:
      walks: ["walk_gen_01"]
      others: ["jog_gen_01", "jump_gen_01"]
      same: ["*_gen_01"]        # table2's test set
"""


def test_experiments_that_differ_in_their_test_sets_share_one_fit(quick_run):
    jobs = scheduled(quick_run, _override(quick_run, "named", NAMED_SETS))
    assert not {"fit_features", "regress", "describe", "voxelize"} & set(jobs)  # table2's, cached
    # two new test sets (`same` is table2's), for the MPPCA and the K-means fit each
    assert jobs["features"] == 4 and jobs["evaluate"] == 4 and jobs["experiment_table"] == 1


def test_named_test_sets_give_one_table_row_per_set_and_method(quick_run):
    named = _override(quick_run, "named", NAMED_SETS)
    snakemake(quick_run, "results/tables/experiments/heldout.csv", configfiles=[named])
    table = pd.read_csv(quick_run / "results/tables/experiments/heldout.csv")
    methods = ["mvrvm", "kmeans", "nearest_neighbour", "kernel_ridge", "mean_pose"]
    assert list(zip(table["test_set"], table["method"], strict=True)) == [
        (s, m) for s in ("walks", "others", "same") for m in methods
    ]
    frames = table.groupby("test_set")["frames"].first()
    assert (frames["walks"], frames["others"], frames["same"]) == (40, 80, 200)
    # the set `same` is table2's test set through the same fit: the same numbers as table2's own table
    table2 = pd.read_csv(quick_run / "results/tables/experiments/table2.csv").drop(columns="test_set")
    same = table[table["test_set"] == "same"].drop(columns="test_set").reset_index(drop=True)
    pd.testing.assert_frame_equal(same, table2)
    measured = pd.read_csv(quick_run / "results/tables/table2.csv").iloc[0]
    assert measured["test frames"] == 200


def test_changing_back_after_a_change_recomputes_nothing(quick_run):
    # a key of the K-means features' directory name: their fits and regressors rerun, the MPPCA ones do not
    changed = _override(quick_run, "votes_changed", "features:\n  kmeans_neighbours: 4\n")
    snakemake(quick_run, configfiles=[changed])
    assert set(scheduled(quick_run)) <= ARTIFACT_RULES
    snakemake(quick_run)
    assert scheduled(quick_run) == {}


def test_same_config_gives_identical_tables(quick_run):
    # the feature fits and everything after them, for Tables 1 and 2 (Figure 4's sweep points and the claims'
    # transfers run the same commands on other inputs, and recomputing them would triple this test's time; the
    # verify test below recomputes one sweep point's descriptors and fit and compares every table)
    tables = [quick_run / f"results/tables/{name}.csv" for name in ("table1", "table2")]
    before = [p.read_bytes() for p in tables]
    snakemake(quick_run, *(str(p.relative_to(quick_run)) for p in tables), "--forcerun", "fit_features")
    assert [p.read_bytes() for p in tables] == before


def _damage(path, how):
    """Damage a cache file as a failing disk or an interrupted copy would, keeping its timestamp (so that Snakemake
    sees nothing): cut its last third, or invert 16 bytes inside the first stored chunk of its descriptors."""
    stat = path.stat()
    data = bytearray(path.read_bytes())
    if how == "truncate":
        data = data[: len(data) * 2 // 3]
    else:
        with h5py.File(path) as f:
            chunk = f["descriptors"].id.get_chunk_info(0)
        at = chunk.byte_offset + chunk.size // 2
        data[at : at + 16] = bytes(b ^ 0xFF for b in data[at : at + 16])
    path.write_bytes(bytes(data))
    os.utime(path, ns=(stat.st_atime_ns, stat.st_mtime_ns))


def test_verify_finds_damaged_caches_and_their_forced_rerun_gives_identical_tables(quick_run):
    tables = sorted((quick_run / "results/tables").rglob("*.csv"))
    before = [p.read_bytes() for p in tables]
    voxels = "results/voxels/irregular6/drunk_gen_00.h5"  # a claims rig's test motion: few dependants
    descriptors = "results/descriptors/circle6-quick/R0.3-r2-4x5x10-soft-body/walk_gen_00.h5"  # a Figure 4 sweep point
    _damage(quick_run / voxels, "truncate")
    _damage(quick_run / descriptors, "flip")
    assert scheduled(quick_run) == {}  # Snakemake alone sees nothing

    proc = run_voxpose("verify", "results", cwd=quick_run)
    assert proc.returncode == 1, proc.stderr
    found = proc.stdout.splitlines()
    assert len(found) == 3, proc.stdout
    assert found[0].startswith(f"{descriptors}: ") and found[0].endswith("(made by rule describe)")
    assert found[1].startswith(f"{voxels}: not a readable HDF5 file") and found[1].endswith("(made by rule voxelize)")

    proc = run_voxpose("verify", "--remove", "results", cwd=quick_run)
    assert proc.returncode == 0, proc.stderr
    again = proc.stdout.splitlines()[-1].split(": snakemake ", 1)[1].split()
    assert again == ["--forcerun", descriptors, voxels]
    jobs = scheduled(quick_run, args=again)
    # exactly those and their dependants: one carving, two descriptor files, one Figure 4 point's fit
    assert (jobs["voxelize"], jobs["describe"], jobs["regress"]) == (1, 2, 1)
    assert not {"generate_bvh", "motion", "table1", "table2"} & set(jobs)
    snakemake(quick_run, *again)
    assert [p.read_bytes() for p in tables] == before
    assert run_voxpose("verify", "results", cwd=quick_run).returncode == 0


def test_every_table_records_what_made_it(quick_run):
    config = yaml.safe_load((quick_run / "config/config.yaml").read_text())
    update_config(config, yaml.safe_load((quick_run / "config/quick.yaml").read_text()))
    tables = sorted((quick_run / "results/tables").rglob("*.csv"))
    assert len(tables) >= 7
    for table in tables:
        if table.parent.name == "experiments" and table.stem not in config["experiments"]:
            continue  # an experiment an earlier test's override config made: its hash is that config's
        meta = json.loads(table.with_name(f"{table.stem}.meta.json").read_text())
        assert meta["config_hash"] == config_hash(config), table
        assert meta["git_commit"] == NOT_GIT  # the test's copy of the workflow is no checkout


REFERENCE = Path(__file__).with_name("reference")


@pytest.mark.parametrize("name", ["table1", "table2", "figure4", "camera_rigs", "robustness"])
def test_quick_tables_equal_the_reference_run(quick_run, name):
    """The quick run's tables as the flat-package layout wrote them (3c95582, before the move to one package per
    stage): a refactoring changes no number. Text cells and integers are compared exactly, real numbers to 1e-9
    relative: OpenBLAS picks its kernels by CPU, and two CPUs sum in other orders (an AMD EPYC and the machine
    that wrote the files differ from the 11th digit on). A deliberate change of results replaces the files in
    ``tests/workflow/reference/`` with the new run's and says why in its commit (last: ``voxpose features`` on the
    screened compiled MPPCA path, issue 22: features move by ~4e-15 and the quick Table 1's unconverged MVRVM fit
    follows them, MPPCA + MVRVM 5.091741 -> 5.091729 deg)."""
    found = list(csv.reader((quick_run / f"results/tables/{name}.csv").open()))
    expected = list(csv.reader((REFERENCE / f"{name}.csv").open()))
    assert [len(row) for row in found] == [len(row) for row in expected]
    for r, (row, ref) in enumerate(zip(found, expected, strict=True)):
        for cell, ref_cell in zip(row, ref, strict=True):
            if _is_real(ref_cell) and _is_real(cell) and not ref_cell.lstrip("-").isdigit():
                assert float(cell) == pytest.approx(float(ref_cell), rel=1e-9), f"{name}.csv row {r}: {row}"
            else:
                assert cell == ref_cell, f"{name}.csv row {r}: {row}"


def _is_real(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def test_overlapping_experiment_is_refused(quick_run):
    text = "experiments:\n  table1:\n    train: ['walk_*']\n    test: ['walk_gen_01']\n"
    bad = _override(quick_run, "overlap", text)
    proc = snakemake(quick_run, "-n", configfiles=[bad], check=False)
    assert proc.returncode != 0
    assert "voxpose: error: config key experiments.table1: test motions also in training: walk_gen_01" in proc.stderr


def test_out_of_range_sweep_value_is_refused_by_the_schema(quick_run):
    bad = _override(quick_run, "sweep", "figure4:\n  n_r: [0, 4]\n")
    proc = snakemake(quick_run, "-n", configfiles=[bad], check=False)
    assert proc.returncode != 0
    assert "voxpose: error: config key figure4.n_r.0:" in proc.stderr
