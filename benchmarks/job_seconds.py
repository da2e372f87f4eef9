"""Where a workflow run's time went: job-seconds per rule, from Snakemake's own records (issue 22).

Usage: ``python benchmarks/job_seconds.py RUN_DIR [--since ISO_TIME]``

Snakemake keeps, per output file, the rule, the job's hash and its start and end times in
``RUN_DIR/.snakemake/metadata`` (one JSON record per file; a job with several outputs writes several records with
the same hash and end time, their start times a few microseconds apart). This groups the records into jobs
and prints, per rule: jobs, job-seconds (the sum of the jobs' wall times), share of the total, the longest job;
then the run's wall span (first start to last end) and the mean number of jobs running at once. On a machine
doing nothing else with ``--cores N`` the job-seconds are close to CPU-seconds: the table says which rules to
make cheaper, and which are many small jobs paying start-up. ``--since`` keeps jobs that started at or after
that time (a partial rerun in a directory with an older run).
"""

import argparse
import json
from collections import defaultdict
from datetime import datetime
from pathlib import Path
from typing import NamedTuple


class Job(NamedTuple):
    rule: str
    start: float
    end: float
    command: str | None  # the shell command, as Snakemake recorded it


def jobs(run_dir: Path, since: float = 0.0) -> list[Job]:
    """Every finished job recorded in ``run_dir``'s Snakemake metadata."""
    seen, commands = {}, {}
    for path in (run_dir / ".snakemake" / "metadata").iterdir():
        record = json.loads(path.read_text())
        start, end = record.get("starttime"), record.get("endtime")
        if record.get("incomplete") or start is None or end is None or start < since:
            continue
        key = (record["rule"], record.get("job_hash"), end)  # a job's outputs share its end, not its start
        seen[key] = min(start, seen.get(key, start))
        commands[key] = record.get("shellcmd")
    return [Job(rule, start, end, commands[rule, h, end]) for (rule, h, end), start in seen.items()]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("--since", type=datetime.fromisoformat, default=None)
    args = parser.parse_args()
    found = jobs(args.run_dir, args.since.timestamp() if args.since else 0.0)
    if not found:
        raise SystemExit(f"job_seconds: no finished jobs recorded in {args.run_dir / '.snakemake/metadata'}")
    per_rule = defaultdict(list)
    for job in found:
        per_rule[job.rule].append(job.end - job.start)
    total = sum(sum(d) for d in per_rule.values())
    span = max(job.end for job in found) - min(job.start for job in found)
    print(f"{'rule':<30} {'jobs':>5} {'job-s':>8} {'share':>6} {'longest s':>10}")
    for rule, durations in sorted(per_rule.items(), key=lambda kv: -sum(kv[1])):
        print(f"{rule:<30} {len(durations):>5} {sum(durations):>8.1f} {sum(durations) / total:>6.1%} "
              f"{max(durations):>10.1f}")  # fmt: skip
    print(f"{'total':<30} {len(found):>5} {total:>8.1f}")
    print(f"wall span {span:.1f} s ({span / 60:.1f} min); {total / span:.2f} jobs running at once on average")


if __name__ == "__main__":
    main()
