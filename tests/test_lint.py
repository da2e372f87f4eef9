"""``snakemake --lint`` leaves only what is justified at the rule: the missing per-rule conda environment, on rules
whose ``rule`` line says why (``# lint:``, explained in the Snakefile)."""

import re
import subprocess
import sys

from tests.helpers import ROOT

CONDA = "Specify a conda environment or container for each rule."


def test_lint_reports_only_justified_items():
    proc = subprocess.run([sys.executable, "-m", "snakemake", "--lint", "--configfile", "config/quick.yaml"],
                          cwd=ROOT, capture_output=True, text=True)  # fmt: skip
    text = proc.stdout + proc.stderr
    assert "Traceback" not in text and "Lints for snakefile" not in text, text
    blocks = re.split(r"(?m)^(?=Lints for )", text)[1:]
    assert blocks, "no lint at all: drop the # lint: markers and this test's allowance"
    for block in blocks:
        head = re.match(r"Lints for rule (\w+) \(line (\d+), (.+)\):", block)
        assert head, block
        titles = re.findall(r"(?m)^    \* (.+?):$", block)
        assert titles == [CONDA], block
        line = open(head[3]).read().splitlines()[int(head[2]) - 1]
        assert line.startswith(f"rule {head[1]}:") and "# lint: no conda/container" in line, line
