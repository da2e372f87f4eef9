"""Choose MPPCA's latent dimension q and the training subsample size on held-out training motions (Section 5).

The paper fixes K = 200 but not q. For each q and subsample size this fits MPPCA on descriptors of some
training motions and prints the mean held-out log-likelihood per descriptor on other training motions, with
the fit time. Test motions are never used.

Usage: python benchmarks/select_mppca_q.py --fit DESC.h5 ... --held-out DESC.h5 ... [--q 2 5 10]
       [--subsample 20000 50000] [--components 200]
(descriptor files from results/descriptors/<rig>/<desc>/, e.g. those of the figure4 experiment's motions)
"""

import argparse
import time

import numpy as np

from voxpose.descriptors.file import read_descriptors
from voxpose.features.model import subsample
from voxpose.features.mppca import MPPCA


def load(paths) -> np.ndarray:
    return np.concatenate([d for p in paths for d in read_descriptors(p)[0] if len(d)])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fit", nargs="+", required=True)
    parser.add_argument("--held-out", nargs="+", required=True)
    parser.add_argument("--q", nargs="+", type=int, default=[2, 5, 10])
    parser.add_argument("--subsample", nargs="+", type=int, default=[20000, 50000])
    parser.add_argument("--components", type=int, default=200)
    parser.add_argument("--tol", type=float, default=1e-5)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    train, held_out = load(args.fit), load(args.held_out)
    print(f"fit rows available {len(train)}, held-out rows {len(held_out)}, d = {train.shape[1]}")
    print(f"{'q':>3} {'subsample':>9} {'iters':>5} {'fit s':>7} {'train LL':>10} {'held-out LL':>11}")
    for n in args.subsample:
        rows = subsample(train, n, args.seed)
        for q in args.q:
            t0 = time.perf_counter()
            model = MPPCA(args.components, n_latent=q, tol=args.tol, random_state=args.seed).fit(rows)
            seconds = time.perf_counter() - t0
            print(
                f"{q:>3} {len(rows):>9} {model.n_iter_:>5} {seconds:>7.1f} {model.log_likelihood_[-1]:>10.3f}"
                f" {model.score(held_out):>11.3f}",
                flush=True,
            )


if __name__ == "__main__":
    main()
