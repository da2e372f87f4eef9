"""Tables 1-2, the claims and the README block from planted runs whose errors are known by construction."""

import json

import numpy as np
import pandas as pd
import pytest

from voxpose.cli.main import main
from voxpose.evaluation import readme_tables
from voxpose.evaluation.tables import FULL_VARYING
from voxpose.io.hdf5 import write_per_motion
from voxpose.motion import canon

KINDS = ("walk", "drunk", "spiral", "jog", "jump")
EXPERIMENT = ("mvrvm", "nearest_neighbour", "kernel_ridge", "mean_pose")
WRIST = [i for i, n in enumerate(canon.ANGLE_NAMES) if "wrist" in n]


def planted_run(directory, offsets: dict, names, frames=30, seed=0):
    """A run's summary.json and predictions.h5: every method's prediction is the truth plus a constant offset per
    method (degrees, on every angle but the still wrists, which every method gets right)."""
    rng = np.random.default_rng(seed)
    directory.mkdir(parents=True)
    motions, methods = {}, {m: [] for m in offsets}
    for name in names:
        true = rng.uniform(-40, 40, (frames, 42))
        true[:, WRIST] = 5.0  # still: predicted exactly
        entry = {
            "true": true,
            "valid": np.ones(frames, bool),
            "offsets": np.zeros((14, 3)),
            "root_positions": np.zeros((frames, 3)),
        }
        for m, off in offsets.items():
            pred = true + off
            pred[:, WRIST] = 5.0
            entry[f"pred_{m}"] = pred
            methods[m].append(pred)
        motions[name] = entry
    write_per_motion(directory / "predictions.h5", "predictions", motions, {})
    total = frames * len(names)
    summary = {"test_frames": total, "n_relevance": 10, "train_frames": 100, "pose_dims": 5, "methods": {}}
    for m, off in offsets.items():
        full = off * 36 / 42
        summary["methods"][m] = {
            "full_body": full,
            "heading": off,
            "left_shoulder": off,
            "right_hip": off,
            "position_mm": 1.0,
            "per_kind": {k: {"full_body": full} for k in KINDS},
        }
    (directory / "summary.json").write_text(json.dumps(summary))
    return [str(directory / "summary.json"), str(directory / "predictions.h5")]


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    d = tmp_path_factory.mktemp("runs")
    spiral = ["spiral_gen_01"]
    five = [f"{k}_gen_01" for k in KINDS]
    ours = planted_run(d / "ours", {"mvrvm": 3.0, "mean_pose": 9.0}, spiral)
    kmeans = planted_run(d / "kmeans", {"mvrvm": 4.0, "mean_pose": 9.0}, spiral)
    at_one = planted_run(d / "at1", {"mvrvm": 2.0, "mean_pose": 9.0}, spiral)  # A&T better: reversed
    t2 = planted_run(d / "t2", {"mvrvm": 2.0, "mean_pose": 8.0}, five)
    out = tmp_path_factory.mktemp("tables")
    boot = ["--bootstrap", "200", "--seed", "3"]
    assert (
        main(
            [
                "table1",
                "--ours",
                *ours,
                "--kmeans",
                *kmeans,
                "--at-one",
                *at_one,
                *boot,
                "--csv",
                str(out / "table1.csv"),
                "--md",
                str(out / "table1.md"),
                "--html",
                str(out / "table1.html"),
            ]
        )
        == 0
    )
    assert (
        main(
            [
                "table2",
                "--run",
                *t2,
                *boot,
                "--csv",
                str(out / "table2.csv"),
                "--md",
                str(out / "table2.md"),
                "--html",
                str(out / "table2.html"),
            ]
        )
        == 0
    )
    assert (
        main(
            [
                "paper-claims",
                "--run",
                "table1_mppca",
                ours[1],
                "--run",
                "table1_kmeans",
                kmeans[1],
                "--run",
                "table1_at_one",
                at_one[1],
                "--run",
                "table2_mppca",
                t2[1],
                "--data-set",
                "planted",
                *boot,
                "--csv",
                str(out / "claims.csv"),
                "--html",
                str(out / "claims.html"),
            ]
        )
        == 0
    )
    return out


def test_table1_full_body_over_42_and_over_the_varying_angles(tables):
    t1 = pd.read_csv(tables / "table1.csv")
    ours = t1[t1["source"] == "voxpose (measured)"].iloc[0]
    # a constant 3-degree error on 36 angles, 0 on the 6 still wrists: 3 * 36 / 42 over 42, 3 over the 36
    assert ours["full body"] == pytest.approx(3 * 36 / 42) and ours[FULL_VARYING] == pytest.approx(3.0)
    assert ours["varying angles"] == 36
    assert ours["full body low"] == pytest.approx(ours["full body"])  # a constant error has no spread
    mean = t1[t1["method"] == "Mean training pose (baseline)"].iloc[0]
    assert mean["body heading angle"] == pytest.approx(9.0) and mean[FULL_VARYING] == pytest.approx(9.0)


def test_table1_page_shows_the_paper_row_and_the_difference(tables):
    page = (tables / "table1.html").read_text()
    assert "<table>" in page and "difference (voxpose - paper)" in page
    assert ">5.2<" in page and ">5.4<" in page and ">6.0<" in page  # the paper's three full-body numbers
    assert f">{3 * 36 / 42 - 5.2:.1f}<" in page  # ours - paper, full body
    assert "36 varying angles" in page


def test_table2_per_type_with_intervals_and_mean_pose(tables):
    t2 = pd.read_csv(tables / "table2.csv")
    ours = t2[t2["source"] == "voxpose (measured)"].iloc[0]
    assert ours["jogging mean pose"] == pytest.approx(8 * 36 / 42) and ours["jogging frames"] == 30
    assert ours[FULL_VARYING] == pytest.approx(2.0)
    page = (tables / "table2.html").read_text()
    assert "drunken walking" in page and ">5.0<" in page and "all five types, 36 varying angles" in page


def test_claim_verdicts_follow_the_planted_errors(tables):
    claims = pd.read_csv(tables / "claims.csv").set_index(["claim", "comparison"])["verdict"]
    kmeans = ("MPPCA features beat K-means (Table 1; also on Table 2)", "MPPCA + MVRVM vs K-means + MVRVM")
    assert claims[kmeans] == "held"
    assert claims[("ours beats Agarwal & Triggs (Table 1)", "MPPCA + MVRVM vs A&T-style, 1 camera")] == "reversed"
    assert (claims.xs("one regressor serves five motion types (Table 2)") == "held").all()
    assert "reversed" in (tables / "claims.html").read_text()


def test_readme_block_is_generated_and_replaced(tables):
    text = readme_tables.markdown(tables)
    assert f"| Our approach (MPPCA + MVRVM), voxpose | {3 * 36 / 42:.1f} [" in text
    assert "| Our approach (MPPCA + MVRVM), paper | 5.2 |  | 8.8 | 6.3 | 3.2 |" in text
    readme = f"intro\n{readme_tables.BEGIN}\nold\n{readme_tables.END}\nrest\n"
    new = readme_tables.replace_block(readme, text)
    assert readme_tables.block(new) == text and new.startswith("intro\n") and new.endswith("rest\n")
    assert readme_tables.normalised("4.1 [3.9, 4.3] 36 varying") == "N [N, N] N varying"


def test_named_blocks_are_rewritten_each_from_its_own_run(tmp_path, tables):
    begin, end = readme_tables.markers("real")
    readme = tmp_path / "README.md"
    readme.write_text(f"a\n{readme_tables.BEGIN}\nold default\n{readme_tables.END}\nb\n{begin}\nold real\n{end}\nc\n")
    assert main(["readme-tables", "--tables", str(tables), "--readme", str(readme), "--block", "real"]) == 0
    text = readme.read_text()
    assert readme_tables.block(text, name="real") == readme_tables.markdown(tables)
    assert readme_tables.block(text) == "old default" and text.endswith(f"{end}\nc\n")
    assert main(["readme-tables", "--tables", str(tables), "--readme", str(readme), "--block", "other"]) == 2


def test_generalisation_block_shows_every_row_with_its_interval():
    df = pd.DataFrame({"held_out": ["cmu_08", "cmu_08"], "method": ["mvrvm", "mean_pose"], "frames": [300, 300],
                       "train_frames": [1500, 1500], "full_body": [10.04, 12.1], "full_body_low": [9.51, 11.8],
                       "full_body_high": [10.66, 12.4], "full_body_varying": [10.9, 13.0],
                       "varying_angles": [39, 39], "heading": [20.0, 60.0], "mpjpe_mm": [81.4, 99.6]})  # fmt: skip
    lines = readme_tables.generalisation_markdown(df)
    assert lines[4] == "| cmu_08 | MPPCA + MVRVM | 300 | 1500 | 10.0 [9.5, 10.7] | 10.9 (39) | 20.0 | 81 |"
    assert lines[5].startswith("| cmu_08 | mean training pose | 300 | 1500 | 12.1 [11.8, 12.4] |") and len(lines) == 6


def test_readme_without_markers_is_a_one_line_error(tmp_path, tables, capsys):
    readme = tmp_path / "README.md"
    readme.write_text("no markers\n")
    assert main(["readme-tables", "--tables", str(tables), "--readme", str(readme)]) == 2
    assert "README.md: expected one" in capsys.readouterr().err and readme.read_text() == "no markers\n"


def test_generalisation_rows_get_intervals_from_their_own_predictions(tmp_path):
    from voxpose.evaluation.generalisation import with_intervals

    names = ["walk_a", "jog_a"]
    mppca = planted_run(tmp_path / "m", {m: 1.0 + i for i, m in enumerate(EXPERIMENT)}, names)
    kmeans = planted_run(tmp_path / "k", {"mvrvm": 7.0}, names)
    df = pd.DataFrame({"held_out": "a", "method": ["mvrvm", "kmeans", "mean_pose"], "full_body": 0.0})
    out = with_intervals(df, {"a": (mppca[1], kmeans[1])}, 100, 0).set_index("method")
    # constant planted errors: the interval is the value itself, 36 of 42 angles move
    assert out.loc["kmeans", "full_body_low"] == pytest.approx(7 * 36 / 42)
    assert out.loc["mean_pose", "full_body_varying"] == pytest.approx(1.0 + EXPERIMENT.index("mean_pose"))
    assert (out["varying_angles"] == 36).all()
