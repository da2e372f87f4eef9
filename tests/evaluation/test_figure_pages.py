"""Figure 4 and the claims' figures as report pages: the caption's numbers are the table's, every label is
legible at the report's width, the page holds the figure and the table."""

import json
import re

import pytest
from matplotlib.text import Text
from PIL import Image

from voxpose.evaluation import claims_figures, figure_pages, figures

# the shipped claims' rigs (config/rigs): as many bars as a real run draws
RIGS = [("circle6", 6, 7.0), ("circle4", 4, 9.5), ("circle8", 8, 7.2), ("circle12", 12, 7.1), ("far6", 6, 7.3),
        ("irregular6", 6, 7.4), ("low6", 6, 7.6)]  # fmt: skip
REPORT_WIDTH = 1100  # px: Snakemake's report shows a result at most this wide (issue 20)


def summary(tmp_path, name, error, baseline=10.0):
    path = tmp_path / f"{name}.json"
    body = {"methods": {"mvrvm": {"full_body": error, "heading": 2 * error}, "mean_pose": {"full_body": baseline}}}
    path.write_text(json.dumps(body | {"n_relevance": 5, "train_frames": 40, "test_frames": 20, "test_gaps": 0}))
    return path


@pytest.fixture
def tables(tmp_path):
    f4 = figures.figure4_table(
        [("n_r", n, summary(tmp_path, f"n{n}", e)) for n, e in ((2, 9.0), (3, 7.5), (4, 8.0))]
        + [("n_components", k, summary(tmp_path, f"k{k}", e)) for k, e in ((100, 8.5), (200, 8.25))]
    )
    rigs = claims_figures.camera_table(
        [{"rig": rig, "cameras": c, "series": s, "summary": summary(tmp_path, f"{rig}{s}", e)}
         for rig, c, e in RIGS for s in ("trained on circle6, not retrained", "retrained on this rig",
                                           "A&T, 6 views concatenated, trained on circle6")]  # fmt: skip
    )
    robust = claims_figures.robustness_table(
        [{"kind": k, "level": lvl, "carving": "inside >= 6 views", "summary": summary(tmp_path, f"{k}{lvl}", 7 + lvl)}
         for k in ("flip", "morph", "limb", "calibration") for lvl in (0.0, 0.5, 2.0)]  # fmt: skip
    )
    return f4, rigs, robust


def test_captions_state_the_tables_numbers(tables):
    f4, rigs, robust = tables
    text = figure_pages.figure4_caption(f4)
    assert "40 training and 20 validation frames" in text and "(10.00)" in text
    assert "radial divisions N_r: best 3 at 7.50, the paper's choice 8.00" in text
    assert "MPPCA components K: best 200 at 8.25, the paper's choice 8.25" in text
    assert "from 7.00 (circle6) to 9.50 (circle4, 4 cameras)" in figure_pages.camera_caption(rigs)
    text = figure_pages.robustness_caption(robust)
    assert "flip (inside >= 6 views): 7.00 clean, 9.00 at level 2" in text
    assert "limb (inside >= 6 views): 7.00 clean, 9.00 at level 2" in text


def test_pages_hold_the_figure_the_caption_and_every_row(tables, tmp_path):
    f4, rigs, robust = tables
    for name, page, table, draw in (("f4", figure_pages.figure4_page, f4, figures.figure4),
                                    ("rigs", figure_pages.camera_page, rigs, claims_figures.camera_figure),
                                    ("robust", figure_pages.robustness_page, robust,
                                     claims_figures.robustness_figure)):  # fmt: skip
        png = tmp_path / f"{name}.png"
        figures.save(draw(table), png, "png")
        page(table, png, tmp_path / f"{name}.html")
        text = (tmp_path / f"{name}.html").read_text()
        assert text.count('<img src="data:image/png;base64,') == 1 and '<p class="caption">' in text
        assert len(re.findall(r"<tr>", text)) == 1 + len(table)  # the header and one row per table row


@pytest.mark.parametrize("which", ["figure4", "cameras", "robustness"])
def test_every_label_is_at_least_10_px_at_the_report_width(tables, tmp_path, which):
    f4, rigs, robust = tables
    fig = {"figure4": lambda: figures.figure4(f4), "cameras": lambda: claims_figures.camera_figure(rigs),
           "robustness": lambda: claims_figures.robustness_figure(robust)}[which]()  # fmt: skip
    figures.save(fig, tmp_path / "f.png", "png")
    with Image.open(tmp_path / "f.png") as image:
        scale = min(1.0, REPORT_WIDTH / image.size[0])
    sizes = [t.get_fontsize() for t in fig.findobj(Text) if t.get_text().strip() and t.get_visible()]
    assert sizes and min(sizes) * 120 / 72 * scale >= 10.0


def test_generalisation_page_states_each_group_against_the_mean_pose(tmp_path):
    """Planted errors: the caption's per-group numbers and ratios are the table's, the page names methods in words
    and shows each interval, the measured MPPCA rows shaded as ours."""
    import pandas as pd

    from voxpose.evaluation.generalisation import generalisation_figure

    rows = []
    for group, (ours, mean) in {"cmu_05": (6.0, 12.0), "bandai_1": (9.0, 10.0)}.items():
        for method, error in (("mvrvm", ours), ("kmeans", ours + 1), ("nearest_neighbour", ours + 2),
                              ("kernel_ridge", ours + 0.5), ("mean_pose", mean)):  # fmt: skip
            rows.append({"held_out": group, "method": method, "frames": 30, "train_frames": 90, "full_body": error,
                         "full_body_low": error - 0.5, "full_body_high": error + 0.5, "full_body_varying": error + 0.1,
                         "varying_angles": 40, "heading": 3 * error, "left_shoulder": error, "right_hip": error,
                         "mpjpe_mm": 10 * error})  # fmt: skip
    table = pd.DataFrame(rows)
    text = figure_pages.generalisation_caption(table)
    assert "cmu_05 6.0 against 12.0 (0.50 of it; heading 18.0)" in text
    assert "bandai_1 9.0 against 10.0 (0.90 of it; heading 27.0)" in text
    generalisation_figure(table, tmp_path / "g.png")
    figure_pages.generalisation_page(table, tmp_path / "g.png", tmp_path / "g.html")
    page = (tmp_path / "g.html").read_text()
    assert page.count('<tr class="ours">') == 2 and "K-means + MVRVM" in page and "mean training pose" in page
    assert "6.0 <small>[5.5, 6.5]</small>" in page and "6.1 (40)" in page and "data:image/png;base64," in page
