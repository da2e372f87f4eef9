"""Measure each rule's peak memory and wall time on a workflow run, to set honest ``resources:`` (issue 9).

Runs Snakemake in a temporary copy of the repository with a ``voxpose`` shim first on PATH: the shim runs the
real command and records its subcommand, wall time, peak resident memory (``ru_maxrss`` of the child) and the
total size of the files it was given that already existed (its inputs). Prints one row per subcommand: jobs,
input MB range, peak RSS MB and wall seconds (max), and the least-squares slopes of peak RSS and seconds over
input MB, which is what the ``resources:`` lambdas in ``workflow/rules/common.smk`` scale by.

Usage: ``python benchmarks/rule_resources.py [--configfile config/quick.yaml] [--cores 2] [TARGET ...]``
(targets default to the whole DAG; name single files to measure a few jobs of a bigger configuration).
"""

import argparse
import json
import os
import shutil
import stat
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

SHIM = """#!{python}
import json, os, resource, subprocess, sys, time
args = sys.argv[1:]
size = sum(os.path.getsize(a) for a in args if os.path.isfile(a))
t0 = time.perf_counter()
rc = subprocess.call([{real!r}, *args])
wall = time.perf_counter() - t0
rss_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
with open({record!r}, "a") as f:
    f.write(json.dumps({{"cmd": args[0], "input_mb": size / 2**20, "rss_mb": rss_mb, "wall_s": wall}}) + "\\n")
sys.exit(rc)
"""


def measure(configfile: str, cores: int, targets: list[str]) -> list[dict]:
    real = shutil.which("voxpose", path=str(Path(sys.executable).parent)) or shutil.which("voxpose")
    if real is None:
        sys.exit("voxpose is not installed beside this Python")
    with tempfile.TemporaryDirectory(prefix="voxpose-resources-") as tmp:
        work, shim_dir = Path(tmp) / "work", Path(tmp) / "shim"
        work.mkdir()
        shim_dir.mkdir()
        for item in ("Snakefile", "workflow", "config"):
            src = ROOT / item
            (shutil.copytree if src.is_dir() else shutil.copy)(src, work / item)
        record = Path(tmp) / "record.jsonl"
        shim = shim_dir / "voxpose"
        shim.write_text(SHIM.format(python=sys.executable, real=real, record=str(record)))
        shim.chmod(shim.stat().st_mode | stat.S_IXUSR)
        env = os.environ | {"PATH": f"{shim_dir}{os.pathsep}{os.environ['PATH']}"}
        cmd = [sys.executable, "-m", "snakemake", "--cores", str(cores), *targets, "--configfile", configfile]
        subprocess.run(cmd, cwd=work, env=env, check=True, stdout=subprocess.DEVNULL)
        return [json.loads(line) for line in record.read_text().splitlines()]


def slope(rows: list[dict], key: str) -> float:
    """Least-squares slope of ``key`` over input MB (nan when the inputs hardly vary)."""
    x = np.array([r["input_mb"] for r in rows])
    y = np.array([r[key] for r in rows])
    if len(rows) < 2 or np.ptp(x) < 0.2 * max(x.max(), 1e-9):
        return float("nan")
    return float(np.polyfit(x, y, 1)[0])


def summarise(rows: list[dict]) -> None:
    by_cmd = defaultdict(list)
    for r in rows:
        by_cmd[r["cmd"]].append(r)
    print(
        f"{'subcommand':16s} {'jobs':>4s} {'input MB':>15s} {'peak MB':>8s} {'max s':>7s} "
        f"{'dMB/dinMB':>10s} {'ds/dinMB':>9s}"
    )
    for cmd, rs in sorted(by_cmd.items()):
        lo, hi = min(r["input_mb"] for r in rs), max(r["input_mb"] for r in rs)
        print(
            f"{cmd:16s} {len(rs):4d} {lo:7.2f}-{hi:7.2f} {max(r['rss_mb'] for r in rs):8.0f} "
            f"{max(r['wall_s'] for r in rs):7.1f} {slope(rs, 'rss_mb'):10.1f} {slope(rs, 'wall_s'):9.2f}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--configfile", default="config/quick.yaml")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--record", type=Path, help="also write the raw per-job rows here (JSON lines)")
    parser.add_argument("targets", nargs="*")
    args = parser.parse_args()
    rows = measure(args.configfile, args.cores, args.targets)
    if args.record:
        args.record.write_text("".join(json.dumps(r) + "\n" for r in rows))
    summarise(rows)


if __name__ == "__main__":
    main()
