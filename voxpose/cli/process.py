"""The ``voxpose`` command as a process (its console script and ``python -m voxpose``): ``main`` with the
cyclic garbage collector set for a short job (issue 22).

A workflow run starts about 400 voxpose processes, most of them a few seconds long, and half of them load
numba, whose type registries and cached kernels leave ~120,000 objects tracked by the collector. CPython
traverses them again at every full collection and at interpreter exit. Measured on one describe job of the
default run (175 frames, 2-core VM, idle; numba's cached kernels):

- exit: 0.17 - 0.30 s from the end of ``main`` to the end of the process, against 0.03 - 0.04 s when every
  live object is first moved to the collector's permanent generation (``gc.freeze``). Nothing is lost: by
  then every output is written and closed, and the operating system frees the memory at once;
- during the run: 224 young, 20 middle and 2 full collections, 0.10 s (``gc.callbacks``), against 15, 1 and
  0 collections, 0.05 s, when a young collection waits for 10,000 net new container objects instead of 700
  (``YOUNG_THRESHOLD``). The numbers the job writes do not depend on when cycles are collected; cyclic
  garbage (rare: the numerical code works on numpy arrays, which hold no references) is freed later.

``benchmarks/bench_process.py`` times a command through both entries: on that describe job 2.00 s wall through
``main`` and 1.74 s through ``run`` (median of 8 alternated runs, CPU 1.99 and 1.74 s). ``main`` itself keeps
the interpreter's defaults: tests and other programs call it inside their own process.
"""

import gc
import sys

from voxpose.cli import job_server

YOUNG_THRESHOLD = 10_000  # net container allocations between young collections (CPython's default: 700)


def run() -> None:
    """Run ``voxpose`` with ``sys.argv``: in a fork of the job server when one is named and accepts it
    (``voxpose.cli.job_server``), else here, skipping the collector's pass over what is left at exit. Exit with the
    command's status."""
    argv = sys.argv[1:]
    status = job_server.run_remote(argv)
    if status is None:
        status = run_here(argv)
        gc.freeze()
    sys.exit(status)


def run_here(argv: list) -> int:
    """Run ``voxpose argv`` in this process, the collector set for a short job; its exit status."""
    gc.set_threshold(YOUNG_THRESHOLD, *gc.get_threshold()[1:])
    from voxpose.cli.main import main

    return main(argv)
