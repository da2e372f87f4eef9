"""MVRVM speed on a problem of the paper's size (Section 6: 1744 training frames, 8-d pose space).

Inputs are Eq. 5-like features: 200-d non-negative vectors summing to 1 (soft assignments of a
frame's descriptors to 200 mixture components), generated from a smooth function of an 8-d latent pose
that moves along smooth trajectories; targets are the latent pose plus noise. Validation frames are the
next 600 frames of the same trajectories (new combinations of the latent coordinates, so partly an
extrapolation). Prints fit time, iterations, relevance vectors kept, prediction time per frame and
training/validation errors.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_mvrvm.py [--frames 1744] [--seed 0]``. One BLAS
thread, as ``voxpose`` subcommands use by default: the fit is a long sequence of small matrix products,
which multithreaded BLAS slows down several-fold on a busy 2-core machine (measured: 108 s against 33 s).
"""

import argparse
import logging
import os
import time

import numpy as np

from voxpose.regression.mvrvm import MVRVM


def trajectories(n_frames: int, dim: int, rng) -> np.ndarray:
    """Smooth latent poses (n_frames, dim): sums of sinusoids with random frequencies and phases."""
    t = np.arange(n_frames)[:, None] / 30.0
    freq = rng.uniform(0.2, 1.5, size=(3, dim))
    phase = rng.uniform(0, 2 * np.pi, size=(3, dim))
    amp = rng.uniform(0.3, 1.0, size=(3, dim))
    return sum(amp[k] * np.sin(2 * np.pi * freq[k] * t + phase[k]) for k in range(3))


def features(z: np.ndarray, centres: np.ndarray, rng, noise: float = 0.05) -> np.ndarray:
    """Soft assignments (n, K) of latent poses to K centres: a softmax of negative squared distances."""
    d2 = ((z[:, None, :] - centres[None, :, :]) ** 2).sum(-1)
    logits = -d2 / 2.0 + noise * rng.standard_normal(d2.shape)
    logits -= logits.max(axis=1, keepdims=True)
    x = np.exp(logits)
    return x / x.sum(axis=1, keepdims=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=1744)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--verbose", action="store_true")
    args = parser.parse_args()
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING)
    rng = np.random.default_rng(args.seed)
    dim, n_features, target_noise = 8, 200, 0.05
    z = trajectories(args.frames + 600, dim, rng)
    centres = rng.uniform(-2.0, 2.0, size=(n_features, dim))
    x = features(z, centres, rng)
    y = z + target_noise * rng.standard_normal(z.shape)
    x_train, y_train, x_val, z_val = x[: args.frames], y[: args.frames], x[args.frames :], z[args.frames :]

    start, cpu = time.perf_counter(), time.process_time()
    model = MVRVM(random_state=args.seed).fit(x_train, y_train)
    fit_s, fit_cpu = time.perf_counter() - start, time.process_time() - cpu
    start = time.perf_counter()
    pred = model.predict(x_val)
    predict_ms = 1e3 * (time.perf_counter() - start) / len(x_val)

    def rms(a, b):
        return float(np.sqrt(np.mean((a - b) ** 2)))

    threads = os.environ.get("OPENBLAS_NUM_THREADS", "default")
    print(f"rows {args.frames}, inputs {n_features}-d, outputs {dim}, BLAS threads {threads}")
    print(f"fit: {fit_s:.2f} s wall, {fit_cpu:.2f} s CPU, {model.n_iter_} iterations, converged {model.converged_}")
    print(f"relevance vectors: {len(model.relevance_)} of {args.frames} ({len(model.relevance_) / args.frames:.1%})")
    print(f"predict: {predict_ms:.4f} ms/frame")
    print(f"noise std estimated {np.round(1 / np.sqrt(model.beta_), 4)} (true {target_noise})")
    print(f"train RMSE {rms(model.predict(x_train), y_train):.4f} (to noisy targets)")
    print(f"validation RMSE {rms(pred, z_val):.4f} (to noise-free targets; target std {y_train.std():.3f})")
    print(f"wall time per iteration {1e3 * fit_s / model.n_iter_:.2f} ms")


if __name__ == "__main__":
    main()
