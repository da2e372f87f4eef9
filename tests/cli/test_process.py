"""The ``voxpose`` process entry (``voxpose.cli.process``): collector settings, exit status, and the entry points."""

import gc
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from voxpose.cli import main as cli
from voxpose.cli.process import YOUNG_THRESHOLD

ROOT = Path(__file__).resolve().parents[2]

# Runs ``python -m voxpose`` (argv from the command line) with an exit handler that reports, after the command,
# the young-generation threshold and how many objects sit in the permanent generation.
_PROBE = (
    "import atexit, gc, runpy, sys\n"
    "atexit.register(lambda: print('probe', gc.get_threshold()[0], gc.get_freeze_count()))\n"
    "sys.argv = ['voxpose', *sys.argv[1:]]\n"
    "runpy.run_module('voxpose', run_name='__main__')\n"
)


@pytest.mark.parametrize(("config", "status"), [("config/config.yaml", 0), ("missing.yaml", 2)])
def test_the_process_raises_the_young_threshold_freezes_at_exit_and_keeps_the_status(config, status):
    proc = subprocess.run(
        [sys.executable, "-c", _PROBE, "check-config", "--base", config], cwd=ROOT, capture_output=True, text=True
    )
    assert proc.returncode == status, proc.stderr
    word, threshold, frozen = proc.stdout.split()
    assert (word, int(threshold)) == ("probe", YOUNG_THRESHOLD)
    assert int(frozen) > 10_000  # everything alive after the command: modules, the config schema, ...
    if status:
        assert proc.stderr.strip().splitlines()[-1].startswith("voxpose: error: ")


def test_main_called_in_process_keeps_the_collector_as_it_was():
    """Tests and programs call ``main`` in their own process: it changes neither threshold nor permanent
    generation."""
    before = gc.get_threshold(), gc.get_freeze_count()
    assert cli.main(["check-config", "--base", str(ROOT / "config" / "config.yaml")]) == 0
    assert (gc.get_threshold(), gc.get_freeze_count()) == before


def test_the_console_script_and_python_m_go_through_the_process_entry():
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    assert scripts["voxpose"] == "voxpose.cli.process:run"
    assert "from voxpose.cli.process import run" in (ROOT / "voxpose" / "__main__.py").read_text()
