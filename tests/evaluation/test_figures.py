"""Figures without pyplot: importing the drawing modules leaves the user's backend alone; files are reproducible."""

import json
import os
import subprocess
import sys

from PIL import Image

from tests.helpers import ROOT
from voxpose.evaluation import claims_figures, figures

DRAWING_MODULES = ("evaluation.figures", "evaluation.claims_figures", "evaluation.gallery", "apply.animation")


def test_importing_the_drawing_modules_keeps_the_backend_and_pyplot_unloaded():
    code = (
        "import sys, matplotlib\n"
        + "".join(f"import voxpose.{m}\n" for m in DRAWING_MODULES)
        + "print(matplotlib.get_backend(), 'matplotlib.pyplot' in sys.modules)\n"
    )
    env = os.environ | {"MPLBACKEND": "svg", "PYTHONPATH": str(ROOT)}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    assert out.stdout.split() == ["svg", "False"]


def summary(tmp_path, name, error):
    path = tmp_path / f"{name}.json"
    method = {"full_body": error, "heading": 2 * error}
    body = {"methods": {"mvrvm": method, "mean_pose": {"full_body": 10.0}}, "n_relevance": 5}
    path.write_text(json.dumps(body | {"train_frames": 40, "test_frames": 20, "test_gaps": 0}))
    return path


def test_figures_save_the_same_bytes_twice_without_a_backend(tmp_path):
    runs = [("n_r", n, summary(tmp_path, f"n{n}", 6.0 + n)) for n in (2, 3, 4)]
    table = figures.figure4_table(runs)
    assert table["validation error (deg)"].tolist() == [8.0, 9.0, 10.0]
    rigs = claims_figures.camera_table(
        [{"rig": "circle6", "cameras": 6, "series": s, "summary": runs[0][2]} for s in ("a", "b")]
    )
    for name, draw in (("f4", lambda: figures.figure4(table)), ("rigs", lambda: claims_figures.camera_figure(rigs))):
        for i in (1, 2):
            figures.save(draw(), tmp_path / f"{name}{i}.png", "png")
        first = (tmp_path / f"{name}1.png").read_bytes()
        assert first == (tmp_path / f"{name}2.png").read_bytes()
        with Image.open(tmp_path / f"{name}1.png") as image:
            assert image.format == "PNG" and min(image.size) > 100
    figures.save(figures.figure4(table), tmp_path / "f4.pdf", "pdf")
    assert (tmp_path / "f4.pdf").read_bytes().startswith(b"%PDF")
