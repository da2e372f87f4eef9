"""Peak memory of each rule on a finished run: its largest job (by input size) run again, from the run's log.

``python benchmarks/largest_jobs.py RUN_DIR SNAKEMAKE_LOG SCRATCH [--skip rule,rule] [--only rule,rule]``

A real-data run is too long to repeat under a memory profiler, and ``/usr/bin/time -v`` over a whole run names
only the largest process, not its rule. This script reads the jobs of a finished run from the log Snakemake
printed (``printshellcmds``: each job's rule, input, output, log and shell command), picks per rule the job with
the most input bytes, and runs its command again in ``SCRATCH/<rule>/`` with every input a symlink to the run's
file (outputs go to the scratch folder, the run is not touched) under ``/usr/bin/time``. Prints per rule: input
MB, peak resident MB of the job, the memory the run asked for it (``mem_mb`` from the log's ``resources:`` line)
and its wall seconds; the profiles' ``mem_mb`` requests (workflow/rules/common.smk,
profiles/README.md) come from such numbers. The commands run with the installed voxpose, so they measure the
current code on the run's inputs.
"""

import argparse
import os
import re
import shutil
import subprocess
from pathlib import Path

FIELDS = ("input", "output", "log")


def read_jobs(log: Path) -> list:
    """Jobs of a Snakemake log: dicts with ``rule``, ``input``, ``output``, ``log`` (lists), ``cmd`` and ``mem_mb``
    (the job's memory request as the log printed it, None when it printed none)."""
    jobs, job = [], None
    for line in log.read_text().splitlines():
        start = re.match(r"^(?:local)?rule (\w+):", line)
        if start:
            job = {"rule": start.group(1), "mem_mb": None, **{field: [] for field in FIELDS}}
            jobs.append(job)
            continue
        text = line.strip()
        if job is None:
            continue
        for field in FIELDS:
            if text.startswith(f"{field}:"):
                job[field] = [p.strip() for p in text[len(field) + 1 :].split(",") if p.strip()]
        request = re.match(r"resources:.*\bmem_mb=(\d+)", text)
        if request:
            job["mem_mb"] = int(request.group(1))
        if text.startswith("Shell command:"):
            job["cmd"] = text[len("Shell command:") :].strip()
    return [job for job in jobs if "cmd" in job]


def largest(jobs: list, run: Path) -> dict:
    """Per rule, (input bytes, job) of its job with the most input bytes."""
    best = {}
    for job in jobs:
        size = sum((run / p).stat().st_size for p in job["input"] if (run / p).is_file())
        if size >= best.get(job["rule"], (-1, None))[0]:
            best[job["rule"]] = (size, job)
    return best


def measure(job: dict, run: Path, folder: Path) -> tuple:
    """Run ``job`` in ``folder`` with symlinked inputs; -> (exit status, peak MB, wall seconds)."""
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    for path in job["input"]:
        target = folder / path
        target.parent.mkdir(parents=True, exist_ok=True)
        if not target.exists():
            os.symlink((run / path).resolve(), target)
    for path in job["output"] + job["log"]:
        (folder / path).parent.mkdir(parents=True, exist_ok=True)
    timing = folder / "time.txt"
    command = ["/usr/bin/time", "-o", str(timing), "-f", "%M %e", "bash", "-c", job["cmd"]]
    with open(folder / "stderr.txt", "w") as err:
        status = subprocess.call(command, cwd=folder, stdout=subprocess.DEVNULL, stderr=err)
    peak_kb, wall = timing.read_text().split()[-2:]
    return status, int(peak_kb) / 1024, float(wall)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="the run's directory (where Snakemake ran)")
    parser.add_argument("log", type=Path, help="the log Snakemake printed for that run")
    parser.add_argument("scratch", type=Path, help="scratch folder for the jobs' outputs")
    parser.add_argument("--skip", default="", help="comma-separated rules not to run")
    parser.add_argument("--only", default="", help="comma-separated rules to run (default: all)")
    args = parser.parse_args()
    skip, only = set(filter(None, args.skip.split(","))), set(filter(None, args.only.split(",")))
    best = largest(read_jobs(args.log), args.run)
    print(f"{'rule':30s} {'input MB':>10s} {'peak MB':>9s} {'asked MB':>9s} {'wall s':>8s}  status")
    for rule, (size, job) in sorted(best.items(), key=lambda item: item[1][0]):
        if rule in skip or (only and rule not in only):
            continue
        status, peak, wall = measure(job, args.run, args.scratch / rule)
        asked = "-" if job["mem_mb"] is None else job["mem_mb"]
        print(f"{rule:30s} {size / 2**20:10.1f} {peak:9.0f} {asked:>9} {wall:8.1f}  {status}", flush=True)


if __name__ == "__main__":
    main()
