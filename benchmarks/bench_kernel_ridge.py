"""Memory and CPU of the kernel ridge baseline's fit (``voxpose.regression.baselines.KernelRidge``) as N grows.

Usage: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_kernel_ridge.py [--rows 2000 4000 9759] [--dims 200]
[--outputs 9] [--max-rows 0 2000]``

The baseline holds the N x N Gram matrix of its training rows and solves one Cholesky system per candidate ridge
on the held-out split, then one on all rows: on an unthinned real training set (~10^4 rows, issue 22) each N x N
array is 0.8 GB, so its copies set the ``regress`` job's peak memory. Rows are uniform random 200-d features,
targets standard normal, held-out groups of 100 rows (as motions); each N is fitted in its own child process,
whose peak resident memory (``ru_maxrss``) and CPU (user + system) are printed, once per ``--max-rows`` (the rows
the ridge is ranked on, ``KernelRidge(max_rows=...)``; 0: every row, as before 9971004).

Measured (6b38077's code, one BLAS thread, machine idle): N = 4000: 3.7 s, 385 MB; N = 9759: 33.2 s, 1891 MB.
The code before 6b38077 (identity matrices added, LAPACK left to copy), timed on the same data by an ad-hoc script
with a default run on the other core: N = 4000 4.6 s and 592 MB against 3.1 s and 384 MB after.
Session 23 (``--rows 9759 --max-rows 2000``, one BLAS thread, idle): 93c8d86 11.7 s, 1596 MB; with the kernel
matrix's distances formed in place and the Cholesky copy a straight one (``squared_distances``,
``cholesky_solve``) 7.6 s, 1596 MB, the same numbers bit for bit; with the final factorisation in the kernel
matrix itself (``cholesky_solve(overwrite_a=True)``) 7.4 s, 884 MB.
"""

import argparse
import multiprocessing
import resource

import numpy as np

from voxpose.regression.baselines import KernelRidge


def _fit(n: int, dims: int, outputs: int, max_rows: int, queue) -> None:
    rng = np.random.default_rng(0)
    x, y = rng.random((n, dims)), rng.standard_normal((n, outputs))
    KernelRidge(kernel_width=2.0, max_rows=max_rows or None, random_state=0).fit(x, y, groups=np.arange(n) // 100)
    usage = resource.getrusage(resource.RUSAGE_SELF)
    queue.put((usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, nargs="+", default=[2000, 4000, 9759])
    parser.add_argument("--dims", type=int, default=200)
    parser.add_argument("--outputs", type=int, default=9)
    parser.add_argument("--max-rows", type=int, nargs="+", default=[0, 2000], help="0: every row")
    args = parser.parse_args()
    context = multiprocessing.get_context("spawn")
    print(f"{'N':>6s} {'ranked on':>9s} {'CPU s':>7s} {'peak MB':>8s} {'N x N MB':>9s}")
    for n in args.rows:
        for max_rows in args.max_rows:
            queue = context.Queue()
            child = context.Process(target=_fit, args=(n, args.dims, args.outputs, max_rows, queue))
            child.start()
            cpu, peak = queue.get()
            child.join()
            ranked = min(n, max_rows) if max_rows else n
            print(f"{n:6d} {ranked:9d} {cpu:7.1f} {peak:8.0f} {n * n * 8 / 2**20:9.0f}", flush=True)


if __name__ == "__main__":
    main()
