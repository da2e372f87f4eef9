"""How the MVRVM fit (Section 3) grows with the training rows: CPU seconds, peak memory, relevance vectors,
convergence and held-out RMSE for N = 1k, 2k, 5k, 10k, 20k rows.

Inputs are a training set's Eq. 5 features (``results/features/.../sets/<train>.h5``) and its motions; the
targets are the pose-PCA coordinates the run regresses (``voxpose.evaluation.run``: heading as a vector,
Eq. 1 at 90 %). N rows are drawn at random (seeded) from all valid frames; sizes above the rows available
print ``n/a``. The next 1000 drawn rows (when there are any left) give a held-out RMSE in pose-PCA units,
so a cheaper fit can be seen not to be a worse one. Each size is fitted in its own child process, so its
peak resident memory (``ru_maxrss``) is its own; CPU is user + system of that child, one BLAS thread.

Two modes. By default one fit at a fixed width (``--width``, or ``--scale`` times the median distance, each
a row of the table) with ``--max-candidates`` and ``--max-iter``. With ``--select``, the workflow's own path
(``voxpose.evaluation.run.fit_mvrvm`` with the ``regression`` section of ``--config``): the kernel-width
selection on held-out motions and the final fit from the chosen candidate, timed together; the table then
shows the chosen scale.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_mvrvm_scaling.py FEATURES MOTION.h5 ...
[--width 0.127 | --scale 0.8] [--max-candidates 2000] [--rows 1000 2000 5000 10000 20000] [--select]``;
``--max-candidates 0`` fits Eq. 3 (a Gaussian on every row). ``--synthetic ROWS`` replaces the real rows by
``bench_mvrvm.py``'s smooth stand-in (200-d soft assignments of an 8-d latent pose; its "motions" are runs of
300 consecutive frames), for sizes beyond a real training set.

Measured (2026-11-26, 2-core VM under load, load average 7-10, so CPU seconds are inflated by contention; one
BLAS thread; ``--select`` with config/config.yaml: scales 0.6/0.8/1, selection_max_rows 2000, max_candidates
2000, max_iter 2000) on the largest real training set (79 motions, 10,323 frames x 200 MPPCA features -> 12
pose-PCA outputs): N = 1000, 2000, 5000, 10000: 93.3, 125.0, 120.2, 124.0 CPU s; peak 312, 431, 584, 791 MB;
735, 1324, 1477, 1679 relevance vectors (73.5, 66.2, 29.5, 16.8 %); none converged (2000 moves); held-out
RMSE 43.47, 35.19, 32.31, 30.24 (1000 held-out rows; 323 at N = 10000). N = 10000 again at load average 1.5-3:
118.4 CPU s, 810 MB, the same 1679 relevance vectors and RMSE. 20000: no real set is that large; on
the stand-in (``--synthetic 21000``, 8 outputs, the same settings, the selection picks 1x) N = 10000, 20000:
70.7, 89.8 CPU s; peak 785, 1175 MB; 1524, 1821 relevance vectors; not converged.
With the 1000-move cap (2026-11-27, ``--select``, config/config.yaml of f4abeeb; the real training set that holds
out CMU subject 1, 79 motions, 9759 frames x 200 MPPCA features -> 12 outputs; one BLAS thread, load average 1-2):
N = 1000, 2000, 5000, 9759: 94.7, 97.2, 98.5, 87.9 CPU s; peak 308, 481, 527, 686 MB; 795, 1253, 1320, 1448
relevance vectors (79.5, 62.6, 26.4, 14.8 %); none converged (1000 moves); held-out RMSE 33.26, 28.11, 25.59 (none
left at 9759). So every real training set fits within 2 minutes on one core.
Width-selection candidates at 500 moves instead of 1000 (9c5a9c3; ``--select --rows 2000 9759`` on the same set,
config/config.yaml with ``selection_max_iter`` 1000 and then 500, the two side by side on 2 cores): N = 2000: 74.3
-> 36.7 CPU s, 1253 -> 1102 relevance vectors, held-out RMSE 28.11 -> 28.39; N = 9759: 72.6 -> 37.8 CPU s, peak
736 -> 644 MB, 1448 -> 1306 relevance vectors; the same scale (0.6) chosen.
Session 23 (cfef108, ``--select --rows 1000 2000 5000 10297``, config/config.yaml, the largest real training set:
79 motions holding out CMU subject 5, 10,297 frames x 200 MPPCA features -> 12 outputs; one BLAS thread, idle):
32.0, 35.1, 29.8, 29.6 CPU s; peak 207, 328, 371, 526 MB; 707, 1074, 1176, 1308 relevance vectors (70.7, 53.7,
23.5, 12.7 %); none converged (1000 moves); held-out RMSE 34.22, 29.02, 26.03 (none left at 10297).
The whole table at the current defaults (2026-11-28, d366896's config/config.yaml: selection 500 moves, final fit
1000; the same set, ``--select --rows 1000 2000 5000 9759``, one BLAS thread, every other process stopped):
N = 1000, 2000, 5000, 9759: 37.7, 51.8, 45.9, 48.6 CPU s; peak 252, 418, 486, 657 MB; 748, 1102, 1186, 1306
relevance vectors (74.8, 55.1, 23.7, 13.4 %); none converged (1000 moves); held-out RMSE 33.40, 28.39, 25.72 (none
left at 9759); scale 0.6 chosen at every N. A 10,000-row real training set fits in under a minute on one core.
Beyond the real sets, on the stand-in at the same defaults (2026-11-28, b98fde0, ``--synthetic 21000 --select --config
config/config.yaml --rows 1000 2000 5000 10000 20000``, ``taskset -c 1``, workflow tests on the other core): 14.3, 22.8,
29.1, 31.9, 42.2 CPU s; peak 201, 335, 484, 653, 933 MB; 467, 862, 1037, 1242, 1298 relevance vectors (46.7, 43.1,
20.7, 12.4, 6.5 %); none converged (1000 moves); held-out RMSE 0.459, 0.376, 0.311, 0.265, 0.244; scale 1 chosen.
A cProfile of the N = 10000 path (wall-clock shares under the same load; 120.8 CPU s): the width selection
(3 fits of 1000 moves on min(N, 2000) rows) 39 % of the time, the final fit 61 %; by kind, move
choice 45 % (exact solves of optimal_alpha 28 %, their companion-matrix eigvals 16 %), full recomputations 23 %
(their eigh 9 %, the residuals over the N rows 3 %), additions 19 % (the new column's kernel over the N rows
5.5 %), the Gram statistics of the 4 fits 2 %. Little of it grows with N beyond the selection's 2000 rows.
"""

import argparse
import multiprocessing
import resource
import time
import warnings
from queue import Empty

import numpy as np
import yaml


def load(features_path: str, motion_paths: list[str]):
    """All valid frames of the motions: features (n, K), pose-PCA targets (n, M) as the run builds them, and
    the motion of each frame (n,)."""
    from voxpose.evaluation.run import _rows
    from voxpose.io.hdf5 import read_per_motion
    from voxpose.motion.data import read_motion
    from voxpose.regression import pose_encoding
    from voxpose.regression.pose_space import PosePCA

    features, _ = read_per_motion(features_path, "features")
    motions = {m.name: m for m in map(read_motion, motion_paths)}
    x, angles, groups = _rows(features, motions, sorted(motions))
    y = pose_encoding.encode(angles, "vector")
    return x, PosePCA(variance=0.9).fit(y).transform(y), groups


def fit_one(x, z, groups, x_val, z_val, fit_args, queue) -> None:
    """Fit (fixed width, or ``fit_mvrvm`` with a config section), report to ``queue``; runs in a child."""
    from voxpose.errors import ConvergenceWarning
    from voxpose.evaluation.run import fit_mvrvm
    from voxpose.regression.mvrvm import MVRVM

    warnings.simplefilter("ignore", ConvergenceWarning)  # the table says whether each fit converged
    before = resource.getrusage(resource.RUSAGE_SELF)
    if "cfg" in fit_args:
        model, table = fit_mvrvm(x, z, groups, fit_args["cfg"], fit_args["seed"])
        label = f"x{next(row['scale'] for row in table if row['width'] == model.kernel_width_):g}"
    else:
        model = MVRVM(random_state=fit_args["seed"], **fit_args["params"]).fit(x, z)
        label = f"{model.kernel_width_:.4g}"
    after = resource.getrusage(resource.RUSAGE_SELF)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    rmse = float(np.sqrt(np.mean(np.sum((model.predict(x_val) - z_val) ** 2, axis=1)))) if len(x_val) else np.nan
    queue.put((label, cpu, after.ru_maxrss / 1024, len(model.relevance_), model.n_iter_, model.converged_, rmse))


def _result(queue, child, n: int) -> tuple:
    """The child's report; exits naming the size when the child ended without one (its traceback is above)."""
    while True:
        try:
            return queue.get(timeout=1.0)
        except Empty:
            if not child.is_alive() and queue.empty():
                message = f"bench_mvrvm_scaling: the fit of N = {n} ended without a result (exit {child.exitcode})"
                raise SystemExit(message) from None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("features", nargs="?")
    parser.add_argument("motions", nargs="*")
    parser.add_argument("--synthetic", type=int, help="this many stand-in rows instead of real features")
    parser.add_argument("--rows", type=int, nargs="+", default=[1000, 2000, 5000, 10000, 20000])
    parser.add_argument("--width", type=float, help="kernel width (default: --scale times the median distance)")
    parser.add_argument("--scale", type=float, nargs="+", default=[0.8], help="each a row of the table")
    parser.add_argument("--max-candidates", type=int, default=2000, help="0: a Gaussian on every row (Eq. 3)")
    parser.add_argument("--max-iter", type=int, default=2000)
    parser.add_argument("--select", action="store_true", help="width selection and final fit as the workflow")
    parser.add_argument("--config", default="config/config.yaml", help="with --select: its regression section")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    from voxpose.regression.kernels import median_pairwise_distance

    if args.synthetic:
        from bench_mvrvm import features, trajectories

        rng = np.random.default_rng(args.seed)
        latent = trajectories(args.synthetic, 8, rng)
        x = features(latent, rng.uniform(-2.0, 2.0, size=(200, 8)), rng)
        z = latent + 0.05 * rng.standard_normal(latent.shape)
        groups = np.arange(args.synthetic) // 300
    else:
        x, z, groups = load(args.features, args.motions)
    order = np.random.default_rng(args.seed).permutation(len(x))
    median = median_pairwise_distance(x, random_state=args.seed)
    if args.select:
        with open(args.config) as f:
            cfg = yaml.safe_load(f)["regression"]
        runs = [("select", {"cfg": cfg, "seed": args.seed})]
        setting = (f"width selection + final fit ({args.config}: scales {cfg['width_scales']}, "
                   f"selection_max_rows {cfg.get('selection_max_rows')}, max_candidates {cfg.get('max_candidates')}, "
                   f"max_iter {cfg['max_iter']})")  # fmt: skip
    else:
        widths = [args.width] if args.width else list(np.multiply(args.scale, median))
        params = {"max_candidates": args.max_candidates or None, "max_iter": args.max_iter}
        runs = [(w, {"params": params | {"kernel_width": w}, "seed": args.seed}) for w in widths]
        setting = f"candidates {args.max_candidates or 'every row'}; max_iter {args.max_iter}"
    print(f"{len(x)} rows x {x.shape[1]} features -> {z.shape[1]} pose-PCA outputs; median distance {median:.4g}; "
          f"{setting}")  # fmt: skip
    columns = ("width", "N", "CPU s", "peak MB", "RVs", "RV %", "moves", "conv", "val RMSE")
    print(" ".join(f"{c:>{w}}" for c, w in zip(columns, (7, 6, 8, 8, 6, 6, 6, 5, 9), strict=True)))
    ctx = multiprocessing.get_context("fork")
    for (name, fit_args), n in [(run, n) for run in runs for n in args.rows]:
        if n > len(x):
            print(f"{name:>7} {n:>6} n/a (only {len(x)} rows)")
            continue
        fit_rows, val_rows = order[:n], order[n : n + 1000]
        queue = ctx.Queue()
        child = ctx.Process(target=fit_one, args=(x[fit_rows], z[fit_rows], groups[fit_rows], x[val_rows], z[val_rows],
                                                  fit_args, queue))  # fmt: skip
        start = time.perf_counter()
        child.start()
        label, cpu, peak, n_rv, n_iter, conv, rmse = _result(queue, child, n)
        child.join()
        wall = time.perf_counter() - start
        print(f"{label:>7} {n:>6} {cpu:>8.1f} {peak:>8.0f} {n_rv:>6} {100 * n_rv / n:>6.1f} {n_iter:>6} "
              f"{'yes' if conv else 'no':>5} {rmse:>9.4f}   ({wall:.0f} s wall)", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
