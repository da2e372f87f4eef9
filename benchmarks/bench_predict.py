"""End-to-end inference speed of ``voxpose predict``: 6-view silhouettes -> 42 angles, frames per second.

Silhouettes of generated motions (one per motion type) are rendered into the default rig (6 cameras,
480 x 480) and kept in memory; the stages of ``voxpose.apply.predict`` then run on them, each timed over the whole
sequence and reported per frame: carving (``Carver`` at l_res = h_sub / 60, after h_sub is measured on the
first frame), surface and basis voxels (``surface_mask``, ``basis_indices``, 200 basis voxels), 3D shape
contexts (``predict.describe``: the default descriptor in the body frame, with the hull's reference heading and
resampling), features (``predict.featurise``: Eq. 5 with MPPCA K = 200, q = 5, the heading senses chosen by the
MPPCA's density and the novelty score, as a workflow model does), regression (MVRVM, inverse PCA, heading
decoding) and the root fit (``apply.root_fit``: the estimated body placed on the hull). The end-to-end line
times the library path itself (``predict.carve`` + ``predict.predict_voxels``); reading PNG files is timed
separately. Each stage and the end to end path run ``--repeats`` times; the minimum is reported (the least
disturbed run on a loaded machine), with each stage's share of the sum of stages and the end-to-end rate
against the 100 frames/s target.

The model: ``--model FILE`` (a workflow's model file); by default a stand-in fitted here on the benchmark's
own frames (MPPCA K = 200, q = 5 with ``--mppca-iter`` EM iterations and a novelty range, pose PCA and MVRVM as
in the workflow), which has the default model's sizes; speed does not depend on how well it is fitted.

Times are CPU times of this process (robust to a loaded machine). Run on one core, as reported:

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 taskset -c 0 .venv/bin/python benchmarks/bench_predict.py

The compiled kernels (``voxpose/kernels.py``) run unless ``VOXPOSE_KERNELS=numpy``; the last line names them.

Measured (ms per frame; 2026-11-25, idle 2-core AMD EPYC VM, load average 0.1, twice with ``--model`` the default
run's Table 2 model, 522 relevance vectors, one repeat, before the novelty stage was split out): carve 4.03 / 3.89,
surface and basis 1.65 / 1.53, 3DSC 6.16 / 6.40, features 4.14 / 4.11, regression 0.01; end to end 16.37 / 15.42
ms, 61.1 / 64.8 frames/s; PNG reading 1.68 / 1.60 ms more (55.4 frames/s from files, worst run). The stand-in
model: 14.58 ms, 68.6 frames/s. The same code on the previous session's VM measured 28.7 ms idle (34.8
frames/s): per-stage times there were about twice these, so the rate depends on the machine. The MPPCA
features are bound by one (n x 201) @ (201 x K(q + 1)) product per frame. The root fit (added 2026-11-26,
stand-in model, measured on a loaded VM, load average 11 on 2 cores, every stage slower than above): 2.61 ms
per frame of 23.20 ms end to end (11 %).

Compiled kernels (2026-11-26, stand-in model, ``taskset -c 0``, nice 15, the VM loaded by other jobs, load
average 4 - 12; four runs alternating ``VOXPOSE_KERNELS=numpy`` and the default): end to end 19.97 / 17.16 /
17.92 / 20.75 ms (50.1 / 58.3 / 55.8 / 48.2 frames/s) on the numpy paths, 13.83 / 13.22 / 13.93 / 13.29 ms
(72.3 / 75.6 / 71.8 / 75.2 frames/s) with the kernels. Best of the four, numpy -> numba, ms per frame: carve
4.41 -> 2.37, surface and basis 0.75 -> 0.72, 3DSC 6.06 -> 3.99, features 3.44 -> 3.51 (no kernel: one BLAS
product), novelty 0.31 -> 0.31, root fit 1.98 -> 1.50. Still short of 100 frames/s: the features' product
and the 3DSC votes (about 8 read-add-writes per pair in the support) are most of what is left.

Body-frame descriptors resampled column by column (``descriptors.body_frame.body_voxels``; 2026-11-27, ``--model`` the
default run's Table 2 model of c13a236 with the heading sense, two repeats, ``taskset -c 1``, nice 5, load average
7.9 - 9.4 from other runs; the old main eddaaa2 first, then this one): 3DSC (body frame and sense included) 13.65 ->
10.06 ms per frame, end to end 26.12 -> 21.14 ms (38.3 -> 47.3 frames/s); the other stages within the load's noise.
On the idle machine (load average 0.4, ``taskset -c 0``, the same model): eddaaa2 21.58 ms end to end (46.3
frames/s) with 11.48 ms of 3DSC; 44b3a5f 17.10 ms (58.5 frames/s) with 7.97 ms of 3DSC (carve 2.44, surface and
basis 0.81, features 3.69, novelty 0.33, root fit 1.62).

Compiled body frame and basis voxels, the shape context kernel's narrower visit, and one evaluation of the MPPCA
per descriptor for the features, the heading senses and the novelty (2026-11-28, ``--model`` the default run's
Table 2 model of 9c5a9c3, ``--repeats 3``, ``taskset -c 0``, every other process stopped, old = d61f547 and new
alternating twice; the novelty stage is now part of features): end to end 15.42 / 15.91 -> 11.57 / 11.58 ms per
frame, 64.8 / 62.9 -> 86.4 / 86.4 frames/s (0.86 x the target); 3DSC (with the senses before) 7.26 / 7.48 -> 3.54 /
3.73 (without them), features + novelty 3.75 / 3.67 -> 4.18 / 4.20 (with the senses), surface and basis 0.66 /
0.68 -> 0.27 / 0.28, carve 1.98 / 1.97 -> 1.89 / 2.02, root fit 1.30 / 1.29 -> 1.27 / 1.30. What is left is the
features' (240 x 201) @ (201 x 1200) product per frame, the shape context votes (about 1.5 million per frame)
and the carving.

The MPPCA posterior after that product in one compiled pass (``features.mppca_kernels``, 2026-11-28, the same model,
``--repeats 3``, ``taskset -c 0``, old = be28b9b and new = 6f8f44f alternating twice, nothing else running but the
VM noisier than the day before): features 4.23 / 4.76 -> 3.59 / 3.92 ms per frame; end to end 12.82 / 12.65 ->
12.11 / 13.28 ms (78.0 / 79.0 -> 82.6 / 75.3 frames/s: the other stages moved by as much as the gain). Earlier the
same day, stash A/B: features 4.62 / 4.27 -> 3.81 / 3.45, end to end 14.42 / 12.46 -> 13.48 / 10.99 ms (91.0
frames/s, the best run). The product itself runs at about 22 GMAC/s on one core (2.4 ms for 240 rows), which is
this CPU's float64 peak: 100 frames/s is not reached on this VM.

The MPPCA scoring screened by a float32 product (``features.mppca_kernels``: components with a provable
responsibility below 1e-30 ruled out, the rest, 1.6 per row, evaluated in float64; 2026-11-28, ``--model`` the
default run's Table 2 model of 1be680c, ``--repeats 3``, ``taskset -c 0``, idle, old = 1be680c and new alternating
twice, each with ``PYTHONPATH`` on its own checkout): features 3.29 / 3.28 -> 2.54 / 2.56 ms per frame; end to end
10.20 / 10.13 -> 9.60 / 9.65 ms, 98.0 / 98.7 -> 104.1 / 103.7 frames/s (carve 1.83 - 1.90, 3DSC 3.44 - 3.58, root
fit 1.18 - 1.21 on both).
"""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from voxpose.apply import predict  # noqa: E402
from voxpose.apply.model_file import PoseModel, load_model  # noqa: E402
from voxpose.apply.root_fit import fit_roots  # noqa: E402
from voxpose.features.model import FeatureModel  # noqa: E402
from voxpose.io.bvh import write_bvh  # noqa: E402
from voxpose.kernels import use_numba  # noqa: E402
from voxpose.motion.generate import generate_motion  # noqa: E402
from voxpose.motion.load import load_motion  # noqa: E402
from voxpose.motion.output_skeleton import OutputSkeleton  # noqa: E402
from voxpose.regression.mvrvm import MVRVM  # noqa: E402
from voxpose.regression.pose_encoding import encode  # noqa: E402
from voxpose.regression.pose_space import PosePCA  # noqa: E402
from voxpose.voxels.cameras import circular_rig  # noqa: E402
from voxpose.voxels.carve import Carver  # noqa: E402
from voxpose.voxels.silhouettes import iter_silhouette_folder, write_silhouette_folder  # noqa: E402
from voxpose.voxels.surface import basis_indices, surface_mask  # noqa: E402
from voxpose.voxels.voxelize import voxelize_motion  # noqa: E402

DESCRIPTOR = {"n_r": 4, "n_e": 5, "n_a": 10, "r_min": 2.0, "r_max": 1 / 3, "soft": True, "normalise": False}
TARGET = 100  # frames/s on one core (issue 22)
VOXELS = {"l_res_fraction": 1 / 60, "min_views": None, "n_basis": 200, "seed": 0}


def cpu(fn, *args):
    start = time.process_time()
    out = fn(*args)
    return out, time.process_time() - start


def stand_in_model(sequences, motions, mppca_iter: int) -> PoseModel:
    """A model of the default sizes fitted on the benchmark's frames (timing only)."""
    model = PoseModel(VOXELS, DESCRIPTOR, None, None, None, "vector", OutputSkeleton.from_motions(motions))
    descriptors = [d for seq in sequences for d in predict.describe(model, seq)[0]]
    cfg = {"n_components": 200, "n_latent": 5, "max_iter": mppca_iter, "tol": 1e-4, "fit_subsample": 20000}
    model.features = FeatureModel.fit("mppca", np.concatenate(descriptors), cfg, seed=0).with_novelty_range(descriptors)
    model.features.estimator.compiled = True  # as load_model sets it for predict
    x = predict.featurise(model, descriptors, None).features
    y = encode(np.concatenate([m.angles for m in motions]), "vector")
    model.pca = PosePCA(0.9).fit(y)
    model.mvrvm = MVRVM(kernel_width="median", random_state=0).fit(x, model.pca.transform(y))
    return model


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=60, help="frames per generated motion (5 motions)")
    parser.add_argument("--model", help="a model file from the workflow instead of the stand-in")
    parser.add_argument("--mppca-iter", type=int, default=3, help="EM iterations of the stand-in MPPCA")
    parser.add_argument("--repeats", type=int, default=3, help="runs of each stage; the minimum is reported")
    args = parser.parse_args()
    rig = circular_rig()
    with tempfile.TemporaryDirectory() as tmp:
        motions = []
        for i, kind in enumerate(("walk", "drunk", "spiral", "jog", "jump")):
            path = Path(tmp) / f"{kind}_bench_{i:02d}.bvh"
            write_bvh(generate_motion(kind, seed=i, n_frames=args.frames, height=1.75), path)
            motions.append(load_motion(path))
        rendered = [voxelize_motion(m, rig, keep_silhouettes=True, progress_every=0) for m in motions]
        if args.model:
            model = load_model(args.model)
        else:
            print(f"fitting a stand-in model (MPPCA K=200, q=5, {args.mppca_iter} EM iterations) ...", flush=True)
            model = stand_in_model(rendered, motions, args.mppca_iter)
        print(f"rig {rig.name}: {len(rig)} cameras {rig.image_size[1]}x{rig.image_size[0]}; model K = "
              f"{model.features.estimator.weights_.shape[0]}, M = {model.pca.n_components_}, "
              f"{len(model.mvrvm.relevance_)} relevance vectors; {len(motions)} x {args.frames} frames")  # fmt: skip
        names = ("carve", "surface+basis", "3DSC", "features", "regression", "root fit")
        stages = {name: np.zeros(args.repeats) for name in names}
        total_e2e, n_frames, io = np.zeros(args.repeats), 0, 0.0
        for seq_ref in rendered:
            sil = seq_ref.silhouettes
            n_frames += len(sil)
            carver = Carver(rig, seq_ref.l_res)
            for r in range(args.repeats):
                voxels, t = cpu(lambda c, frames: [c(s) for s in frames], carver, sil)
                stages["carve"][r] += t
                _, t = cpu(lambda frames: [basis_indices(v[surface_mask(v)], 200, 0) for v in frames], voxels)
                stages["surface+basis"][r] += t
                (descriptors, h0), t = cpu(predict.describe, model, seq_ref)
                stages["3DSC"][r] += t
                described, t = cpu(predict.featurise, model, descriptors, h0)
                stages["features"][r] += t
                valid = described.counts > 0
                angles, t = cpu(predict.regress, model, described.features, valid, described.heading_offsets())
                stages["regression"][r] += t
                _, t = cpu(fit_roots, seq_ref, angles, valid, model.skeleton)
                stages["root fit"][r] += t
                seq, t_carve = cpu(predict.carve, model, iter(sil), rig)
                _, t_rest = cpu(predict.predict_voxels, model, seq)
                total_e2e[r] += t_carve + t_rest
            folder = Path(tmp) / "sil"
            write_silhouette_folder(sil[:10], rig, folder)
            _, t = cpu(lambda f: list(iter_silhouette_folder(f, rig)), folder)
            io += t / 10 * len(sil)
    best = {name: t.min() for name, t in stages.items()}
    t_sum = sum(best.values())
    print(f"{'stage':<16} {'ms/frame':>9} {'frames/s':>9} {'share':>6}   (minimum of {args.repeats} runs, CPU time)")
    for name, t in best.items():
        print(f"{name:<16} {1e3 * t / n_frames:9.2f} {n_frames / t:9.1f} {100 * t / t_sum:5.1f}%")
    print(f"{'sum of stages':<16} {1e3 * t_sum / n_frames:9.2f} {n_frames / t_sum:9.1f}")
    e2e = total_e2e.min()
    print(f"{'end to end':<16} {1e3 * e2e / n_frames:9.2f} {n_frames / e2e:9.1f}   (predict.carve + "
          f"predict.predict_voxels; {n_frames / e2e / TARGET:.2f} x the target of {TARGET} frames/s)")  # fmt: skip
    print(f"{'PNG reading':<16} {1e3 * io / n_frames:9.2f} {n_frames / io:9.1f}   (6 files per frame, not included)")
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())} (1, 5, 15 min); kernels: "
          f"{'numba' if use_numba() else 'numpy'} (VOXPOSE_KERNELS)")  # fmt: skip


if __name__ == "__main__":
    main()
