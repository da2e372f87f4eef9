"""k-means with Hamerly's bounds (``voxpose.features.kmeans_bounds``) against plain Lloyd iterations, same result.

Usage: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_kmeans.py [--descriptors FILE ...] [--rows 20000]
[--clusters 200]``

The rows are ``--rows`` descriptors drawn (seeded) from the given descriptor files (a workflow's
``results/descriptors/...``), or, without files, histogram-like stand-ins (sparse non-negative rows in overlapping
groups). ``KMeans.fit`` runs twice on them: as it is, and with its assignment replaced by plain Lloyd's
(every distance every iteration, ``nearest_centres``); the CPU time of each fit, the distances computed, and whether
the centres and labels are equal (they must be) are printed.

Measured (2026-11-28, one core, idle; the 10 training motions' descriptors of a default run, 20000 rows of 200
bins, K = 200, 43 iterations): plain 4.33 s, bounds 2.97 s (0.69x) in an ad-hoc A/B of the two commits; inside a
default MPPCA fit job (70 iterations) its k-means took 5.95 -> 4.13 s by the log's timestamps. This script
(2026-11-28, ``taskset -c 0``, idle, ``--descriptors`` the default run's
``R0.3333-r2-4x5x10-soft-body/*_gen_0[0-4]*.h5``): 20000 rows, K = 200, 76 iterations; plain Lloyd 4.84 s
CPU (1,520,000 rows computed), Hamerly bounds 2.94 s (619,093 rows computed), 0.61x; centres and labels equal.
"""

import argparse
import time

import numpy as np

import voxpose.features.kmeans as kmeans_module
from voxpose.descriptors.file import read_descriptor_file
from voxpose.features.kmeans import KMeans, nearest_centres


class _PlainLloyd:
    """The assignment of plain Lloyd iterations, with ``BoundedAssignment``'s interface."""

    def __init__(self, X, chunk_size):
        self._x, self._chunk, self.recomputed = X, chunk_size, X.shape[0]

    def assign(self, centres):
        return nearest_centres(self._x, centres, self._chunk)[0]


def _rows(files, n, seed):
    rng = np.random.default_rng(seed)
    if files:
        rows = np.concatenate([np.concatenate(read_descriptor_file(f).frames) for f in files])
    else:
        base = rng.random((40, 200)) ** 6
        rows = base[rng.integers(0, 40, 4 * n)] + 0.5 * rng.random((4 * n, 200)) ** 3
    return rows[np.sort(rng.choice(len(rows), min(n, len(rows)), replace=False))].astype(np.float32)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--descriptors", nargs="*", default=[], help="descriptor files (HDF5) to draw rows from")
    parser.add_argument("--rows", type=int, default=20000)
    parser.add_argument("--clusters", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    X = _rows(args.descriptors, args.rows, args.seed)
    counted = {}

    def counting(cls):
        class Counting(cls):
            def assign(self, centres):
                labels = super().assign(centres)
                counted[cls.__name__] = counted.get(cls.__name__, 0) + self.recomputed
                return labels

        return Counting

    fits = {}
    for name, cls in (("plain Lloyd", _PlainLloyd), ("Hamerly bounds", kmeans_module.BoundedAssignment)):
        original = kmeans_module.BoundedAssignment
        kmeans_module.BoundedAssignment = counting(cls)
        try:
            start = time.process_time()
            fits[name] = (KMeans(args.clusters, random_state=args.seed).fit(X), time.process_time() - start)
        finally:
            kmeans_module.BoundedAssignment = original
    (plain, t_plain), (bounded, t_bounded) = fits.values()
    print(f"{X.shape[0]} rows x {X.shape[1]}, K = {args.clusters}, {plain.n_iter_} iterations")
    print(f"{'assignment':<16} {'CPU s':>7} {'rows computed':>14}")
    for (name, (_, seconds)), rows in zip(fits.items(), counted.values(), strict=True):
        print(f"{name:<16} {seconds:7.2f} {rows:14d}")
    same = np.array_equal(plain.cluster_centers_, bounded.cluster_centers_) and np.array_equal(
        plain.labels_, bounded.labels_
    )
    print(f"ratio {t_bounded / t_plain:.2f}x; centres and labels equal: {same}")


if __name__ == "__main__":
    main()
