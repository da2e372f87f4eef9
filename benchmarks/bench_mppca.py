"""Speed of the MPPCA E-step and of a full fit at the paper's size (d = 200, K = 200, q = 10).

Data: histogram-like descriptors from a planted mixture. Each of 200 prototypes is a sparse distribution over
the 200 bins (Dirichlet, concentration 0.05 per bin); a descriptor blends its prototype with a fixed neighbour
prototype (weight uniform in [0, 0.3], a one-dimensional family per prototype), draws ~300 Poisson votes from
the blend, and weights bin b by 1 / cbrt(V_b) for random bin volumes V_b, as the 3D shape context does; it is
divided by the vote count. The rows are non-negative, sparse (most bins zero) and clustered.

The estimator runs in float64 only; the float32 E-step timed here goes through the same (private) kernels to
show what float32 would buy and cost.

Run: ``.venv/bin/python benchmarks/bench_mppca.py`` (``--help`` for sizes).
"""

import argparse
import logging
import os
import resource
import time

import numpy as np

from voxpose.features.mppca import MPPCA, _accumulate, _log_joint_chunks, _logsumexp_rows, _Params, _project


def histogram_descriptors(n, d=200, n_prototypes=200, votes=300, seed=0):
    """``n`` planted histogram-like rows (n, d), float64; see the module docstring."""
    rng = np.random.default_rng(seed)
    prototypes = rng.dirichlet(np.full(d, 0.05), size=n_prototypes)
    neighbour = rng.permutation(n_prototypes)
    bin_weight = 1.0 / np.cbrt(rng.uniform(0.2, 5.0, size=d))
    label = rng.integers(n_prototypes, size=n)
    blend = rng.uniform(0.0, 0.3, size=(n, 1))
    rates = votes * ((1.0 - blend) * prototypes[label] + blend * prototypes[neighbour[label]])
    return rng.poisson(rates) * bin_weight / votes


def timed(function, *args):
    start = time.perf_counter()
    result = function(*args)
    return time.perf_counter() - start, result


def responsibilities(X, proj, chunk_size):
    """Responsibilities (n, K) and log densities (n,) through the E-step kernel in ``proj``'s dtype."""
    resp, log_p = [], []
    for _, log_joint, _, _ in _log_joint_chunks(X, proj, chunk_size):
        log_p.append(_logsumexp_rows(log_joint))
        resp.append(np.exp(log_joint - log_p[-1][:, None]))
    return np.concatenate(resp), np.concatenate(log_p)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-fit", type=int, default=50_000)
    parser.add_argument("--n-estep", type=int, default=100_000)
    parser.add_argument("--components", type=int, default=200)
    parser.add_argument("--latent", type=int, default=10)
    parser.add_argument("--tol", type=float, default=1e-4)
    parser.add_argument("--max-iter", type=int, default=100)
    parser.add_argument("--chunk-sizes", type=int, nargs="+", default=[1024, 4096])
    parser.add_argument("--repeats", type=int, default=3, help="E-step timings report the fastest repeat")
    args = parser.parse_args()
    logging.basicConfig(level=logging.INFO, format="    %(name)s: %(message)s")
    print(f"BLAS threads: default; load average at start {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")

    X = histogram_descriptors(max(args.n_fit, args.n_estep))
    zeros, row_sum = np.mean(X == 0), X.sum(axis=1).mean()
    print(f"data: {X.shape[0]} x {X.shape[1]}, {zeros:.0%} zero entries, mean row sum {row_sum:.3f}")

    model = MPPCA(args.components, n_latent=args.latent, tol=args.tol, max_iter=args.max_iter, random_state=0)
    start_cpu = time.process_time()
    seconds, _ = timed(model.fit, X[: args.n_fit])
    print(
        f"fit: {args.n_fit} rows, {seconds:.1f} s wall ({time.process_time() - start_cpu:.1f} s CPU), "
        f"{model.n_iter_} EM iterations, converged {model.converged_}, {model.n_reseeded_} re-seeded, "
        f"final mean log-likelihood {model.log_likelihood_[-1]:.4f}"
    )

    params = _Params(model.weights_, model.means_, model.components_, model.noise_variance_)
    X_estep = X[: args.n_estep]
    seconds = {}
    for chunk in args.chunk_sizes:
        for dtype in (np.float64, np.float32):
            proj = _project(params, dtype)
            seconds[dtype, chunk] = min(timed(_accumulate, X_estep, proj, chunk)[0] for _ in range(args.repeats))
            print(
                f"E-step {dtype.__name__} chunk {chunk}: {args.n_estep} rows, {seconds[dtype, chunk]:.2f} s "
                f"(load average {os.getloadavg()[0]:.1f})"
            )
    for chunk in args.chunk_sizes:
        ratio = seconds[np.float64, chunk] / seconds[np.float32, chunk]
        print(f"E-step speed ratio float64 / float32, chunk {chunk}: {ratio:.2f}")

    chunk = args.chunk_sizes[0]
    resp64, ll64 = responsibilities(X_estep, _project(params, np.float64), chunk)
    resp32, ll32 = responsibilities(X_estep, _project(params, np.float32), chunk)
    print(f"float32 vs float64: max |responsibility difference| {np.abs(resp32 - resp64).max():.2e}")
    print(f"float32 vs float64: max |log-density difference| {np.abs(ll32 - ll64).max():.2e}")
    print(f"peak resident memory: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20:.2f} GiB")


if __name__ == "__main__":
    main()
