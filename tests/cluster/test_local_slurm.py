"""The quick configuration on a real local SLURM cluster (issue 9); opt-in, never part of the normal suite.

Run with ``VOXPOSE_SLURM_TEST=1 pytest tests/cluster -s`` as root with ``pip install -e '.[slurm]'``; the work is
done by ``tests/cluster/local_slurm.py`` (see its docstring), which can also be run directly.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(
    os.environ.get("VOXPOSE_SLURM_TEST") != "1",
    reason="local SLURM test: set VOXPOSE_SLURM_TEST=1 (needs root and voxpose[slurm])",
)


def test_quick_config_on_local_slurm_matches_local_run():
    script = Path(__file__).with_name("local_slurm.py")
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True)
    print(proc.stdout)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-6000:]
    assert "PASSED" in proc.stdout
