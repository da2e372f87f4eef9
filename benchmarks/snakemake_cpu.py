"""CPU time of the Snakemake process itself over a whole workflow run, for scheduler settings side by side (issue 22).

Each variant (extra Snakemake arguments; "" is the repository's profile as shipped) runs the workflow from scratch in
a fresh copy of ``Snakefile``, ``workflow``, ``config`` and ``profiles``; the user + system CPU seconds of the main
Snakemake process (not of its jobs) are read from ``/proc/PID/stat`` twice a second until it exits (Linux only).
Printed per variant: wall seconds, the main process's CPU seconds and their share of the wall time.

Why: Snakemake 9 re-evaluates its ready jobs (their params, resources and input sizes) after each
``max-jobs-per-timespan`` timespan, and every finished job starts one more such re-evaluation timer, so with the
default ``100/1s`` a run of N jobs re-evaluates about N times a second by its end. ``profiles/default`` sets a 5 s
timespan (the run then waits up to 5 s for the last timer at its end).

    python benchmarks/snakemake_cpu.py [--configfile config/quick.yaml] [--cores 2] \\
        --variant "--max-jobs-per-timespan 100/1s" --variant ""
"""

import argparse
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def cpu_seconds(pid: int) -> float:
    """User + system CPU seconds of process ``pid`` (``/proc/PID/stat`` fields 14 and 15)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def run(configfile: str, cores: int, extra: str) -> tuple[float, float]:
    """(wall seconds, main-process CPU seconds) of one run from scratch with ``extra`` arguments."""
    with tempfile.TemporaryDirectory(prefix="voxpose-snakemake-cpu-") as tmp:
        for item in ("Snakefile", "workflow", "config", "profiles"):
            src = ROOT / item
            (shutil.copytree if src.is_dir() else shutil.copy)(src, Path(tmp) / item)
        cmd = [sys.executable, "-m", "snakemake", "--cores", str(cores), "--configfile", configfile,
               *shlex.split(extra)]  # fmt: skip
        env = os.environ | {"PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}  # voxpose
        start = time.perf_counter()
        proc = subprocess.Popen(cmd, cwd=tmp, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        used = 0.0
        while proc.poll() is None:
            try:
                used = cpu_seconds(proc.pid)
            except (FileNotFoundError, ProcessLookupError):  # exited between poll() and the read
                break
            time.sleep(0.5)
        wall = time.perf_counter() - start
        if proc.returncode != 0:
            sys.exit(f"snakemake {extra!r} failed with exit code {proc.returncode}")
        return wall, used


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--configfile", default="config/quick.yaml")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--variant", action="append", help="extra Snakemake arguments (repeatable; default: '')")
    args = parser.parse_args()
    print(f"{'variant':40s} {'wall s':>8s} {'snakemake CPU s':>16s} {'share':>6s}   ({args.configfile}, "
          f"--cores {args.cores}; load average {os.getloadavg()[0]:.2f})")  # fmt: skip
    for extra in args.variant or [""]:
        wall, used = run(args.configfile, args.cores, extra)
        print(f"{extra or '(profile as shipped)':40s} {wall:8.1f} {used:16.1f} {100 * used / wall:5.1f}%", flush=True)


if __name__ == "__main__":
    main()
