"""One voxpose command run as a process through ``main`` alone and through ``voxpose.cli.process.run`` (issue 22).

Usage: ``python benchmarks/bench_process.py [--repeats N] -- COMMAND ARGS...`` in a finished run's folder, e.g.
``-- describe results/voxels/circle6/spiral_gen_01.h5 --params '{...}' -o /tmp/d.h5`` (a rule's shell command
without its leading ``voxpose``; write outputs outside ``results``).

``run`` raises the collector's young threshold and freezes every live object before the interpreter exits
(``voxpose.cli.process``). The two entries are alternated ``--repeats`` times; printed per entry: the median wall
and CPU seconds (the child's user + system time), then the ratio run / main.
"""

import argparse
import resource
import statistics
import subprocess
import sys
import time

ENTRIES = {
    "main": "import sys; from voxpose.cli.main import main; sys.exit(main())",
    "run": "from voxpose.cli.process import run; run()",
}


def _once(code: str, command: list[str]) -> tuple[float, float]:
    """Wall and CPU seconds of one process running ``voxpose COMMAND`` through ``code``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", code, *command], check=True, capture_output=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=8)
    parser.add_argument("command", nargs=argparse.REMAINDER, help="-- then the voxpose command and its arguments")
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        parser.error("give the voxpose command after --")
    times = {name: [] for name in ENTRIES}
    for _ in range(args.repeats):
        for name, code in ENTRIES.items():
            times[name].append(_once(code, command))
    medians = {name: [statistics.median(column) for column in zip(*t, strict=True)] for name, t in times.items()}
    for name, (wall, cpu) in medians.items():
        print(f"{name:>4}: wall {wall:.3f} s, CPU {cpu:.3f} s (median of {args.repeats})")
    (wall_main, cpu_main), (wall_run, cpu_run) = medians["main"], medians["run"]
    print(f"run / main: wall {wall_run / wall_main:.2f}, CPU {cpu_run / cpu_main:.2f}")


if __name__ == "__main__":
    main()
