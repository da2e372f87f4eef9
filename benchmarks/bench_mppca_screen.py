"""The compiled MPPCA scoring's and E-step's float32 screen (``voxpose.features.mppca_kernels``) against the float64
numpy path.

Usage: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_mppca_screen.py MODEL DESCRIPTORS... [--rows 24000]
[--block 240] [--repeats 5]``

MODEL is a workflow's feature model (``results/features/<train>/<rig>/<desc>/mppca-.../model.h5``), DESCRIPTORS
descriptor files of the same descriptor (``results/descriptors/<rig>/<desc>/*.h5``); the first ``--rows`` of their
descriptors are scored both ways. Printed: the components evaluated in float64 per row (of K), the largest
differences of the log densities and responsibilities between the two paths, the largest numpy responsibility the
screen set to 0 (must be below 1e-30), and the CPU milliseconds per ``--block`` rows (240: one predicted frame at
the default settings) of each path, the fastest of ``--repeats``, with their ratio. Then the EM's E-step
(``mppca._accumulate``) on the first ``--estep-rows`` rows (20,000: a feature fit's subsample) both ways: the largest
relative difference of its sufficient statistics and the CPU seconds of one E-step, fastest of ``--repeats``.

Measured (2026-11-28, ``OPENBLAS_NUM_THREADS=1 taskset -c 0``, idle; a default run's MPPCA fitted on its 10 training
motions, K = 200, q = 5, ``features/n10-f3c45f30f7/...``, and 24,000 rows of its ``R0.3333-r2-4x5x10-soft-body``
descriptors): 1.60 components evaluated per row (median 1, max 7 of 200); log densities within 3.8e-12 (9.7e-12
relative), responsibilities within 2.9e-13, the largest screened-out responsibility 7.4e-31; CPU per 240 rows
3.52 ms on the numpy path, 2.22 ms screened (0.63x). The E-step (2026-11-29, the same way, the same model and
rows, on a machine that scored them in 4.43 and 2.76 ms): statistics within 7.36e-15, CPU 0.362 -> 0.216 s (0.60x).
With the screen's bounds formed over a coordinate-major product (267c750; 2026-11-29, alternated with 34453a4's
code, the same way, n10-f3c45f30f7's model and its first three default motions' rows): screened 2.32 -> 2.02-2.04
CPU ms per 240 rows (numpy path 3.69-3.79), E-step 0.193 -> 0.162-0.164 s; the same differences from the numpy
path (log densities 3.5e-12, statistics 5.42e-15).
With the exact evaluation's sums in eight local accumulators (c20e52c; 2026-11-29, ``OPENBLAS_NUM_THREADS=1 taskset
-c 0``, idle, alternated twice with cfef108's code; a real-data MPPCA, ``features/n79-5b94e29cc7/...``, and 24,000 rows
of walk_cmu_02_01, jog_bandai2_run_normal_001 and jump_cmu_02_04, 1.97 components evaluated per row): screened
2.09-2.10 -> 1.95-1.98 CPU ms per 240 rows, E-step 0.171 -> 0.159-0.162 s; the same differences from the numpy path
(log densities 3.47e-12, responsibilities 2.49e-13, statistics 6.71e-15).
"""

import argparse
import time

import numpy as np

from voxpose.descriptors.file import read_descriptor_file
from voxpose.features import mppca as mppca_module
from voxpose.features.model import FeatureModel
from voxpose.features.mppca import MPPCA


def _rows(files, n):
    rows, total = [], 0
    for path in files:
        frames = read_descriptor_file(path).frames
        rows.append(np.concatenate(frames).astype(np.float64))
        total += len(rows[-1])
        if total >= n:
            break
    return np.concatenate(rows)[:n]


def _cpu_per_block(function, rows, block, repeats):
    best = np.inf
    for _ in range(repeats):
        start = time.process_time()
        function(rows)
        best = min(best, time.process_time() - start)
    return best / len(rows) * block * 1e3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("model")
    parser.add_argument("descriptors", nargs="+")
    parser.add_argument("--rows", type=int, default=24000)
    parser.add_argument("--block", type=int, default=240)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--estep-rows", type=int, default=20000)
    args = parser.parse_args()
    numpy_path = FeatureModel.load(args.model).estimator
    if not isinstance(numpy_path, MPPCA):
        raise SystemExit(f"bench_mppca_screen: {args.model} is not an MPPCA feature model")
    screened = MPPCA.from_arrays(*numpy_path.to_arrays())
    screened.compiled = True
    rows = _rows(args.descriptors, args.rows)
    proba, log_p = numpy_path.proba_and_score(rows)
    fast_proba, fast_log_p = screened.proba_and_score(rows)  # compiles (or loads) the kernel before the timing
    chunks = mppca_module._scored_chunks(rows, screened._projection(), screened._screening(), screened.chunk_size)
    n_kept = np.concatenate([n for _, _, n in chunks])
    n_components = numpy_path.weights_.shape[0]
    print(f"{len(rows)} rows x {rows.shape[1]}, K = {n_components}, q = {numpy_path.components_.shape[2]}")
    print(f"components evaluated in float64 per row: mean {n_kept.mean():.2f}, median {np.median(n_kept):.0f}, "
          f"max {n_kept.max()} of {n_components}")  # fmt: skip
    print(f"largest |log p difference| {np.abs(fast_log_p - log_p).max():.3g} "
          f"(relative {np.max(np.abs(fast_log_p - log_p) / np.abs(log_p)):.3g}); largest |responsibility difference| "
          f"{np.abs(fast_proba - proba).max():.3g}; largest numpy responsibility screened out "
          f"{proba[fast_proba == 0.0].max(initial=0.0):.3g}")  # fmt: skip
    slow = _cpu_per_block(numpy_path.proba_and_score, rows, args.block, args.repeats)
    fast = _cpu_per_block(screened.proba_and_score, rows, args.block, args.repeats)
    print(f"CPU ms per {args.block} rows: numpy path {slow:.2f}, screened {fast:.2f} ({fast / slow:.2f}x)")
    _estep(screened, rows[: args.estep_rows], args.repeats)


def _estep(model, rows, repeats) -> None:
    """The E-step's statistics and CPU both ways (``mppca._accumulate`` without and with the screen)."""
    proj, screen, chunk = model._projection(), model._screening(), model.chunk_size
    exact = mppca_module._accumulate(rows, proj, chunk)
    fast = mppca_module._accumulate(rows, proj, chunk, screen)
    worst = max(float(np.max(np.abs(np.subtract(a, b)) / np.maximum(np.max(np.abs(a)), 1e-300)))
                for a, b in zip(exact, fast, strict=True))  # fmt: skip
    seconds = {}
    for name, extra in [("numpy", ()), ("screened", (screen,))]:
        seconds[name] = np.inf
        for _ in range(repeats):
            start = time.process_time()
            mppca_module._accumulate(rows, proj, chunk, *extra)
            seconds[name] = min(seconds[name], time.process_time() - start)
    print(f"E-step on {len(rows)} rows: statistics within {worst:.3g} relative (to each one's largest entry); CPU s "
          f"numpy path {seconds['numpy']:.3f}, screened {seconds['screened']:.3f} "
          f"({seconds['screened'] / seconds['numpy']:.2f}x)")  # fmt: skip


if __name__ == "__main__":
    main()
