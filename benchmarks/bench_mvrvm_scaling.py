"""How the MVRVM fit (Section 3) grows with the training rows, on real features: seconds, peak memory and
relevance vectors for N = 1k, 2k, 5k, 10k, 20k rows.

Inputs are a training set's Eq. 5 features (``results/features/.../sets/<train>.h5``) and its motions; the
targets are the pose-PCA coordinates the run regresses (``voxpose.evaluation.run``: heading as a vector,
Eq. 1 at 90 %). N rows are drawn at random (seeded) from all valid frames; sizes above the rows available
print ``n/a``. The next 1000 drawn rows (when there are any left) give a held-out RMSE in pose-PCA units,
so a cheaper fit can be seen not to be a worse one. Each size is fitted in its own child process, so its
peak resident memory (``ru_maxrss``) is its own; CPU is user + system of that child, one BLAS thread.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_mvrvm_scaling.py FEATURES MOTION.h5 ...
[--width 0.127 | --scale 0.8] [--max-candidates 2000] [--rows 1000 2000 5000 10000 20000]``;
``--max-candidates 0`` fits Eq. 3 (a Gaussian on every row), the old behaviour. ``--synthetic ROWS`` replaces
the real rows by ``bench_mvrvm.py``'s smooth stand-in (200-d soft assignments of an 8-d latent pose), for
sizes beyond a real training set.
"""

import argparse
import multiprocessing
import resource
import time

import numpy as np


def load(features_path: str, motion_paths: list[str]):
    """All valid frames of the motions: features (n, K) and pose-PCA targets (n, M), as the run builds them."""
    from voxpose.evaluation.run import _rows
    from voxpose.io.hdf5 import read_per_motion
    from voxpose.motion.data import read_motion
    from voxpose.regression import pose_encoding
    from voxpose.regression.pose_space import PosePCA

    features, _ = read_per_motion(features_path, "features")
    motions = {m.name: m for m in map(read_motion, motion_paths)}
    x, angles, _ = _rows(features, motions, sorted(motions))
    y = pose_encoding.encode(angles, "vector")
    return x, PosePCA(variance=0.9).fit(y).transform(y)


def fit_one(x, z, x_val, z_val, width, max_candidates, max_iter, seed, queue) -> None:
    from voxpose.regression.mvrvm import MVRVM

    wall, before = time.perf_counter(), resource.getrusage(resource.RUSAGE_SELF)
    model = MVRVM(kernel_width=width, max_candidates=max_candidates, max_iter=max_iter, random_state=seed)
    model.fit(x, z)
    after = resource.getrusage(resource.RUSAGE_SELF)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    rmse = float(np.sqrt(np.mean(np.sum((model.predict(x_val) - z_val) ** 2, axis=1)))) if len(x_val) else np.nan
    queue.put((time.perf_counter() - wall, cpu, after.ru_maxrss / 1024, len(model.relevance_), model.n_iter_,
               model.converged_, rmse))  # fmt: skip


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
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    from voxpose.regression.kernels import median_pairwise_distance

    if args.synthetic:
        from bench_mvrvm import features, trajectories

        rng = np.random.default_rng(args.seed)
        latent = trajectories(args.synthetic, 8, rng)
        x = features(latent, rng.uniform(-2.0, 2.0, size=(200, 8)), rng)
        z = latent + 0.05 * rng.standard_normal(latent.shape)
    else:
        x, z = load(args.features, args.motions)
    order = np.random.default_rng(args.seed).permutation(len(x))
    median = median_pairwise_distance(x, random_state=args.seed)
    cands = args.max_candidates or None
    print(f"{len(x)} rows x {x.shape[1]} features -> {z.shape[1]} pose-PCA outputs; median distance {median:.4g}; "
          f"candidates {cands or 'every row'}; max_iter {args.max_iter}")  # fmt: skip
    columns = ("width", "N", "wall s", "CPU s", "peak MB", "RVs", "RV %", "moves", "conv", "val RMSE")
    print(" ".join(f"{c:>{w}}" for c, w in zip(columns, (7, 6, 8, 8, 8, 6, 6, 6, 5, 9), strict=True)))
    ctx = multiprocessing.get_context("fork")
    widths = [args.width] if args.width else list(np.multiply(args.scale, median))
    for width, n in [(w, n) for w in widths for n in args.rows]:
        if n > len(x):
            print(f"{width:>7.4g} {n:>6} n/a (only {len(x)} rows)")
            continue
        fit_rows, val_rows = order[:n], order[n : n + 1000]
        queue = ctx.Queue()
        child = ctx.Process(target=fit_one, args=(x[fit_rows], z[fit_rows], x[val_rows], z[val_rows], width,
                                                  cands, args.max_iter, args.seed, queue))  # fmt: skip
        child.start()
        wall, cpu, peak, n_rv, n_iter, conv, rmse = queue.get()
        child.join()
        print(f"{width:>7.4g} {n:>6} {wall:>8.1f} {cpu:>8.1f} {peak:>8.0f} {n_rv:>6} {100 * n_rv / n:>6.1f} "
              f"{n_iter:>6} {str(conv):>5} {rmse:>9.4f}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
