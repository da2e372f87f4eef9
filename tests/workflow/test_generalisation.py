"""End to end: the subject-held-out table of the quick run (``conftest.quick_run``), the jobs it needs alone, and
the fits it shares."""

import json

import pandas as pd
import pytest
import yaml

from tests.helpers import ROOT, scheduled
from voxpose import workflow_config as wc

pytestmark = pytest.mark.workflow  # slow: deselect with -m "not workflow"

QUICK = yaml.safe_load((ROOT / "config/quick.yaml").read_text())
TARGETS = ("results/tables/generalisation.csv", "results/tables/experiments/table2.csv")
METHODS = ["mvrvm", "kmeans", "nearest_neighbour", "kernel_ridge", "mean_pose"]
RUN = "circle6-quick/R0.3333-r2-4x5x10-soft-body/mppca-K16-q3"


def test_identical_training_sets_are_fitted_once(quick_run):
    # holding out gen_01 trains on every *_gen_00 motion and tests on every *_gen_01 one: table2's experiment;
    # --forceall: every job the targets need, as a run from nothing would schedule
    alone = scheduled(quick_run, args=("--forceall", *TARGETS[:1]))
    both = scheduled(quick_run, args=("--forceall", *TARGETS))
    # two training sets (gen_00 and gen_01 held out), each with an MPPCA and a K-means fit and regressor
    assert (alone["fit_features"], alone["regress"], alone["evaluate"]) == (4, 4, 4)
    # table2 adds its table, not a fit, a regressor or an evaluation
    assert {k: v for k, v in both.items() if alone.get(k) != v} == {"experiment_table": 1}


def test_the_table_has_one_row_per_group_and_method_and_each_group_its_frames(quick_run):
    table = pd.read_csv(quick_run / "results/tables/generalisation.csv")
    groups = [g["name"] for g in QUICK["generalisation"]["groups"]]
    assert list(zip(table["held_out"], table["method"], strict=True)) == [(g, m) for g in groups for m in METHODS]
    names = wc.generated_motions(QUICK["generated"])
    for group, rows in table.groupby("held_out"):
        held = [n for n in names if n.endswith(group.removeprefix("gen"))]
        assert (rows["frames"] == sum(names[n][2] for n in held)).all()  # every frame of the group's motions
        assert (rows["train_frames"] == sum(f for n, (_, _, f) in names.items() if n not in held)).all()
    assert table[["full_body", "heading", "mpjpe_mm"]].gt(0).all().all()
    assert (quick_run / "results/tables/generalisation.md").read_text().startswith("# Generalisation")
    assert (quick_run / "results/figures/generalisation.png").stat().st_size > 10000


def test_a_held_out_group_is_never_trained_on_and_shares_table2s_run(quick_run):
    train = [n for n in wc.generated_motions(QUICK["generated"]) if n.endswith("_gen_01")]
    test = [n.replace("_gen_01", "_gen_00") for n in train]
    summary = json.loads((quick_run / f"results/runs/{wc.motion_set_tag(train)}/{RUN}/sets/"
                                  f"{wc.motion_set_tag(test)}/summary.json").read_text())  # fmt: skip
    assert summary["train"] == sorted(train) and summary["test"] == sorted(test)
    # gen_01 held out is table2's run: the same numbers as table2's own table
    table = pd.read_csv(quick_run / "results/tables/generalisation.csv")
    gen_01 = table[table["held_out"] == "gen_01"].drop(columns=["held_out", "train_frames"]).reset_index(drop=True)
    table2 = pd.read_csv(quick_run / "results/tables/experiments/table2.csv").drop(columns="test_set")
    pd.testing.assert_frame_equal(gen_01[table2.columns], table2)  # the intervals' columns are the table's own
    assert scheduled(quick_run, args=TARGETS) == {}
