"""Speed of rendering and carving at the default settings, and the voxel counts of Figure 2.

Runs on generated motions (``voxpose.motion.generate``, written as BVH and loaded like real data) or on
BVH files given with ``--bvh``; one core (BLAS limited to one thread). Times are CPU times of this
process (robust to a shared machine); each frame is timed ``--repeats`` times and the best counts.
Prints per-frame times and frames
per second of rendering (body model + exact silhouettes), carving (at l_res = h_sub / 60), surface and
basis voxels, and of the whole ``voxelize_motion``, then occupied / surface / basis counts (mean, min,
max) to compare with the paper's "about 4000 / 2000 / 200" (Figure 2).

    .venv/bin/python benchmarks/bench_render_carve.py [--frames 120] [--bvh FILE ...]
"""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from voxpose.io.bvh import write_bvh  # noqa: E402
from voxpose.motion.generate import generate_motion  # noqa: E402
from voxpose.motion.load import load_motion  # noqa: E402
from voxpose.voxels.body import body_ellipsoids  # noqa: E402
from voxpose.voxels.cameras import circular_rig  # noqa: E402
from voxpose.voxels.carve import Carver  # noqa: E402
from voxpose.voxels.render import render_silhouettes  # noqa: E402
from voxpose.voxels.surface import basis_indices, surface_mask  # noqa: E402
from voxpose.voxels.voxelize import subject_shifts, voxelize_motion  # noqa: E402


def generated_motions(frames: int, folder: Path) -> list:
    paths = []
    for i, kind in enumerate(("walk", "drunk", "spiral", "jog", "jump")):
        path = folder / f"{kind}_bench_{i:02d}.bvh"
        write_bvh(generate_motion(kind, seed=i, n_frames=frames, height=1.75), path)
        paths.append(path)
    return paths


def per_frame(fn, items, repeats: int) -> tuple[list, float]:
    """Results of ``fn`` over ``items`` and the mean over items of the best of ``repeats`` CPU times (s)."""
    out, best = [], []
    for item in items:
        times = []
        for _ in range(repeats):
            start = time.process_time()
            result = fn(item)
            times.append(time.process_time() - start)
        out.append(result)
        best.append(min(times))
    return out, float(np.mean(best))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=120, help="frames per generated motion")
    parser.add_argument("--bvh", nargs="*", default=[], help="BVH files instead of generated motions")
    parser.add_argument("--repeats", type=int, default=3, help="timings per frame; the best one counts")
    args = parser.parse_args()
    reps = args.repeats
    rig = circular_rig()
    print(f"rig {rig.name}: {len(rig)} cameras, {rig.image_size[1]}x{rig.image_size[0]} px")
    with tempfile.TemporaryDirectory() as tmp:
        paths = [Path(p) for p in args.bvh] or generated_motions(args.frames, Path(tmp))
        motions = [load_motion(p) for p in paths]
    header = f"{'motion':<28} {'frames':>6} {'render ms':>9} {'carve ms':>9} {'surf+basis':>10} {'voxelize':>9}"
    print(header)
    totals = {"render": 0.0, "carve": 0.0, "surface": 0.0, "voxelize": 0.0, "frames": 0}
    counts = {"occupied": [], "surface": [], "basis": []}
    for motion in motions:
        n = motion.n_frames
        _, t_body = per_frame(lambda m: body_ellipsoids(m).translated(subject_shifts(m, rig)), [motion], reps)
        t_body /= n
        el = body_ellipsoids(motion).translated(subject_shifts(motion, rig))
        sils, t_silhouettes = per_frame(lambda f, el=el: render_silhouettes(el.frame(f), rig), range(n), reps)
        t_render = t_body + t_silhouettes
        seq = voxelize_motion(motion, rig, progress_every=0)
        carver = Carver(rig, seq.l_res)
        voxels, t_carve = per_frame(carver, sils, reps)

        def surface_and_basis(ijk):
            mask = surface_mask(ijk)
            return basis_indices(ijk[mask])

        _, t_surface = per_frame(surface_and_basis, voxels, reps)
        _, t_vox = per_frame(lambda m: voxelize_motion(m, rig, progress_every=0), [motion], 1)
        t_vox /= n
        for key, values in seq.counts().items():
            counts[key].extend(values[~seq.empty].tolist())
        print(
            f"{motion.name:<28} {n:>6} {1e3 * t_render:>9.2f} {1e3 * t_carve:>9.2f} {1e3 * t_surface:>10.2f} "
            f"{1e3 * t_vox:>9.2f}"
        )
        for key, value in (
            ("render", t_render),
            ("carve", t_carve),
            ("surface", t_surface),
            ("voxelize", t_vox),
        ):
            totals[key] += value * n
        totals["frames"] += n
    frames = totals["frames"]
    per = {key: totals[key] / frames for key in ("render", "carve", "surface", "voxelize")}
    print()
    print(f"over {frames} frames, one core, CPU time, best of {reps} per frame (voxelize_motion: one run):")
    both = per["render"] + per["carve"]
    for label, seconds in (
        ("render (body model + 6 silhouettes)", per["render"]),
        ("carve (visual hull at h/60)", per["carve"]),
        ("surface + basis voxels", per["surface"]),
        ("render + carve", both),
        ("voxelize_motion (all of it)", per["voxelize"]),
    ):
        print(f"  {label:<38} {1e3 * seconds:6.2f} ms/frame = {1 / seconds:6.1f} fps")
    print(f"  carve / render time ratio: {per['carve'] / per['render']:.2f}")
    print()
    print("voxel counts per frame (paper, Figure 2: about 4000 occupied, 2000 surface, 200 basis):")
    for key, values in counts.items():
        values = np.array(values)
        print(f"  {key:<9} mean {values.mean():7.0f}  min {values.min():6d}  max {values.max():6d}")


if __name__ == "__main__":
    main()
