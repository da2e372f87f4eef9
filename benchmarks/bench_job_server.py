"""Jobs of a finished run, each run alone and through the job server (``voxpose.cli.job_server``, issue 22).

Usage: ``python benchmarks/bench_job_server.py RUN_DIR [--repeats N] [--rules a,b]`` with the run's ``voxpose`` on
PATH. For each rule (default: the rules with the most job-seconds), the job of median length in the run's metadata
(``.snakemake/metadata``, read by ``job_seconds.jobs``) is run again in RUN_DIR with its outputs and log
redirected to a temporary folder: as its own process (``voxpose ...``, as without the server) and as a command
served by a server started the way the workflow starts it, alternated ``--repeats`` times. Printed per rule: the
jobs in the run, the median wall seconds alone and served (the command's wall time, which covers its fork's), their
ratio, and the seconds the run's jobs of that rule would save at that rate. The server's start-up (its preload,
once per run) is printed apart.
"""

import argparse
import os
import shlex
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

from job_seconds import jobs

from voxpose.cli import job_server

OUTPUTS = ("-o", "--output", "--log", "--regressor", "--baselines", "--fit", "--predictions", "--angles")
DEFAULT_RULES = ("regress", "fit_features", "describe", "features", "voxelize", "silhouette_contexts",
                 "transfer_features", "voxelize_degraded")  # fmt: skip


def median_jobs(run: Path, rules) -> dict:
    """rule -> (number of jobs, the shell command of its job of median wall time) from the run's metadata."""
    per_rule = {}
    for job in jobs(run):
        if job.rule in rules and job.command:
            per_rule.setdefault(job.rule, []).append(job)
    picked = {}
    for rule, found in per_rule.items():
        ordered = sorted(found, key=lambda job: job.end - job.start)
        picked[rule] = (len(found), ordered[len(ordered) // 2].command)
    return picked


def redirected(command: str, folder: str) -> list:
    """The command's words with every output (``OUTPUTS``) moved into ``folder``."""
    words = shlex.split(command)
    for i, word in enumerate(words[:-1]):
        if word in OUTPUTS:
            words[i + 1] = os.path.join(folder, f"{i}-{Path(words[i + 1]).name}")
    return words


def timed(words: list, env: dict) -> float:
    start = time.perf_counter()
    subprocess.run(words, env=env, check=True, capture_output=True)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a finished run's folder (the repository copy it ran in)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--rules", default=",".join(DEFAULT_RULES))
    args = parser.parse_args()
    os.chdir(args.run)
    picked = median_jobs(Path("."), args.rules.split(","))
    threads = dict.fromkeys(job_server.SNAKEMAKE_THREAD_VARIABLES, "1")
    alone_env = {k: v for k, v in os.environ.items() if k != job_server.ENV} | threads
    with tempfile.TemporaryDirectory() as folder:
        log = os.path.join(folder, "server.log")
        start = time.perf_counter()
        handle = job_server.start(log)
        served_env = os.environ | threads
        while not os.path.exists(served_env[job_server.ENV]):
            time.sleep(0.01)
        print(f"server ready after {time.perf_counter() - start:.2f} s (preload, once per run)")
        try:
            print(f"{'rule':<22}{'jobs':>6}{'alone s':>9}{'served s':>10}{'ratio':>7}{'saved job-s':>13}")
            total = 0.0
            for rule, (n_jobs, command) in picked.items():
                words = redirected(command, folder)
                alone, served = [], []
                for _ in range(args.repeats):
                    alone.append(timed(words, alone_env))
                    served.append(timed(words, served_env))
                a, s = statistics.median(alone), statistics.median(served)
                total += n_jobs * (a - s)
                print(f"{rule:<22}{n_jobs:>6}{a:>9.2f}{s:>10.2f}{s / a:>7.2f}{n_jobs * (a - s):>13.1f}")
            print(f"total saved, at these rates: {total:.0f} job-s")
        finally:
            job_server.stop(handle)
        refused = [line for line in Path(log).read_text().splitlines() if "refused" in line]
        print(f"served: {Path(log).read_text().count(': exit 0 after ')}, refused: {len(refused)}")


if __name__ == "__main__":
    main()
