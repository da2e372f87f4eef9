"""Speed of the 3D shape context fast path (lookup table) against the reference, on human-like voxel sets.

Each frame is a synthetic figure 1.75 m tall, voxelised at ``l_res = h_sub / 60`` (2.9 cm) as in Sun et
al. (2006), Section 4: a union of ellipsoids (torso, pelvis, head, and upper and lower arms and legs
between randomly posed joints), its surface voxels (occupied with an empty 6-neighbour, about 2000) and
200 basis voxels drawn from them. Both paths describe the same frames; the script prints the frame
statistics, milliseconds per frame, descriptors per second and the speed ratios, for hard and soft votes,
and the largest difference between the two paths. The fast path is timed one frame per call (median
over frames) and as ``describe_frames`` over all frames with a pool of 1 and 2 threads (total time per
frame), after one untimed pass that grows its code table.

    python benchmarks/bench_shape_context.py [--frames 40] [--reference-frames 3] [--basis 200] [--threads 1 2]

Times are wall-clock and process CPU time (summed over threads); other jobs on the machine inflate the
wall-clock numbers, so the load average is printed too.

Measured (2026-11-28, 2-core VM, ``OPENBLAS_NUM_THREADS=1 taskset -c 0 ... --frames 40 --threads 1 2``, every other
process stopped, old = d61f547 and new = this code alternating twice), soft votes, ms per frame, one frame per
call (median): 3.04 / 3.03 -> 2.30 / 2.38; ``describe_frames`` with 1 thread 3.21 / 3.29 -> 2.49 / 2.66, with 2
threads 3.10 / 3.14 -> 2.40 / 2.64; the reference 121-126 ms. The kernel now visits only the surface voxels within
the support's reach and reads each pair's bins already reflected (``descriptors/lut_kernels.py``); the
descriptors are unchanged.
"""

import argparse
import os
import time

import numpy as np
from scipy import ndimage

from voxpose.descriptors.lut import ShapeContextTable
from voxpose.descriptors.shape_context import shape_contexts
from voxpose.kernels import use_numba

HEIGHT = 1.75  # metres
VOXELS_PER_HEIGHT = 60  # l_res = h_sub / 60 (Section 4)


def _unit(v):
    return v / np.linalg.norm(v)


def _limb_direction(rng, mean, spread):
    """A random unit direction around ``mean`` (radians of spread per axis)."""
    return _unit(np.asarray(mean, dtype=float) + rng.normal(scale=spread, size=3))


def figure_ellipsoids(rng):
    """``(centre, semi_axes, rotation)`` of the body parts of one random pose, metres, Y up, feet at 0."""
    parts = [
        ((0.0, 1.22, 0.0), (0.22, 0.30, 0.15), np.eye(3)),  # torso
        ((0.0, 0.92, 0.0), (0.21, 0.12, 0.15), np.eye(3)),  # pelvis
        ((0.0, 1.61, 0.0), (0.11, 0.14, 0.12), np.eye(3)),  # head
    ]
    chains = [  # (root joint, mean direction, segment lengths, segment radii)
        ((-0.24, 1.42, 0.0), (-0.5, -1.0, 0.0), (0.30, 0.27), (0.07, 0.06)),
        ((0.24, 1.42, 0.0), (0.5, -1.0, 0.0), (0.30, 0.27), (0.07, 0.06)),
        ((-0.11, 0.88, 0.0), (0.0, -1.0, 0.1), (0.43, 0.42), (0.10, 0.075)),
        ((0.11, 0.88, 0.0), (0.0, -1.0, 0.1), (0.43, 0.42), (0.10, 0.075)),
    ]
    for root, mean, lengths, radii in chains:
        joint = np.array(root)
        direction = _limb_direction(rng, mean, 0.5)
        for length, radius in zip(lengths, radii, strict=True):
            end = joint + length * direction
            axis = _unit(end - joint)
            helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
            side = _unit(np.cross(axis, helper))
            rotation = np.column_stack([axis, side, np.cross(axis, side)])
            parts.append(((joint + end) / 2, (length / 2 + radius / 2, radius, radius), rotation))
            joint, direction = end, _limb_direction(rng, direction, 0.4)
    return parts


def figure_voxels(rng, n_basis):
    """Surface voxels ``(N, 3)``, ``n_basis`` basis voxels and the occupied count of one random pose."""
    l_res = HEIGHT / VOXELS_PER_HEIGHT
    parts = figure_ellipsoids(rng)
    reach = np.array([[c - max(a), c + max(a)] for c, a, _ in parts for c in [np.asarray(c)]])
    low = reach[:, 0].min(axis=0) - 2 * l_res
    shape = np.ceil((reach[:, 1].max(axis=0) + 2 * l_res - low) / l_res).astype(int)
    occupied = np.zeros(shape, dtype=bool)
    for centre, semi_axes, rotation in parts:
        lo = np.floor((np.asarray(centre) - max(semi_axes) - low) / l_res).astype(int)
        hi = np.ceil((np.asarray(centre) + max(semi_axes) - low) / l_res).astype(int)
        ijk = np.stack(np.meshgrid(*[np.arange(a, b) for a, b in zip(lo, hi, strict=True)], indexing="ij"), -1)
        local = (low + (ijk + 0.5) * l_res - centre) @ rotation / semi_axes
        occupied[lo[0] : hi[0], lo[1] : hi[1], lo[2] : hi[2]] |= (local * local).sum(axis=-1) <= 1.0
    interior = ndimage.binary_erosion(occupied, structure=ndimage.generate_binary_structure(3, 1))
    surface = np.argwhere(occupied & ~interior)
    basis = surface[rng.choice(len(surface), size=min(n_basis, len(surface)), replace=False)]
    return surface, basis, int(occupied.sum())


def _timed(fn, *args, **kwargs):
    wall, cpu = time.perf_counter(), time.process_time()
    result = fn(*args, **kwargs)
    return result, time.perf_counter() - wall, time.process_time() - cpu


def _line(name, wall_ms, cpu_ms, n_desc):
    print(
        f"  {name:<20s}: {wall_ms:8.2f} ms/frame wall, {cpu_ms:7.2f} CPU ms/frame; "
        f"{1e3 * n_desc / wall_ms:9,.0f} descriptors/s"
    )


def bench_mode(frames, soft, n_ref, threads):
    """Time both paths on ``frames`` for one voting mode, print the results, return the descriptors."""
    l_res = HEIGHT / VOXELS_PER_HEIGHT
    table, build, _ = _timed(ShapeContextTable, VOXELS_PER_HEIGHT, soft=soft)
    pairs = [(surface, basis) for surface, basis, _ in frames]
    table.describe_frames(pairs)  # warm-up: grows the code table once, as the first frames of a motion do
    single = [_timed(table.describe, surface, basis) for surface, basis in pairs]  # (descriptors, wall, CPU)
    pooled = {n: _timed(table.describe_frames, pairs, threads=n) for n in threads}
    ref = []
    for surface, basis in pairs[:n_ref]:
        points, centres = (surface + 0.5) * l_res, (basis + 0.5) * l_res
        ref.append(_timed(shape_contexts, points, centres, l_res=l_res, h_sub=HEIGHT, soft=soft))
    n_desc = np.mean([len(basis) for _, basis in pairs])
    wall, cpu = (1e3 * np.array([f[k] for f in single]) for k in (1, 2))
    ref_wall, ref_cpu = (1e3 * np.array([f[k] for f in ref]) for k in (1, 2))
    diff = max(np.abs(r[0] - f[0]).max() for r, f in zip(ref, single, strict=False))
    for result, _, _ in pooled.values():
        diff = max(diff, max(np.abs(a - f[0]).max() for a, f in zip(result, single, strict=True)))
    print(f"\n[{'soft' if soft else 'hard'} votes] offset table built in {1e3 * build:.0f} ms")
    _line("fast, 1 frame/call", np.median(wall), np.median(cpu), n_desc)
    print(f"  {'':<20s}  (minimum {wall.min():.2f} ms wall, {cpu.min():.2f} CPU ms)")
    for n, (_, w, c) in pooled.items():
        _line(f"fast, {n} thread{'s' if n > 1 else ''}", 1e3 * w / len(pairs), 1e3 * c / len(pairs), n_desc)
    _line("reference", np.median(ref_wall), np.median(ref_cpu), n_desc)
    ratio_wall = np.median(ref_wall) / np.median(wall[:n_ref])
    ratio_cpu = np.median(ref_cpu) / np.median(cpu[:n_ref])
    print(f"  ratio reference / fast (1 frame/call, same frames): {ratio_wall:.1f}x wall, {ratio_cpu:.1f}x CPU")
    for n, (_, w, _) in pooled.items():
        per_frame = 1e3 * w / len(pairs)
        print(
            f"  ratio reference / fast ({n} thread{'s' if n > 1 else ''}): {np.median(ref_wall) / per_frame:.1f}x wall"
        )
    print(f"  max |fast - reference| = {diff:.2e} (all fast variants agree with each other to within it)")
    return [f[0] for f in single]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=40, help="frames described by the fast path")
    parser.add_argument("--reference-frames", type=int, default=3, help="of those, frames also run by the reference")
    parser.add_argument("--basis", type=int, default=200, help="basis voxels per frame")
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2], help="thread counts of the frame pool")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)

    rng = np.random.default_rng(args.seed)
    frames = [figure_voxels(rng, args.basis) for _ in range(args.frames)]
    n_ref = max(1, min(args.reference_frames, args.frames))
    occupied, surface, basis = np.mean([[f[2], len(f[0]), len(f[1])] for f in frames], axis=0)
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"{args.frames} frames, reference on {n_ref}; load average {load} (1, 5, 15 min), {os.cpu_count()} cores")
    print(f"voxels per frame: {occupied:.0f} occupied, {surface:.0f} surface, {basis:.0f} basis")

    bench_mode(frames, False, n_ref, args.threads)
    soft = bench_mode(frames, True, n_ref, args.threads)
    in_support, non_empty = [], []
    for (surface, basis, _), desc in zip(frames, soft, strict=True):
        r = np.linalg.norm(surface[None] - basis[:, None], axis=2)
        in_support.append(((r >= 2.0) & (r < VOXELS_PER_HEIGHT / 3)).sum(axis=1).mean())
        non_empty.append((desc > 0).sum(axis=1).mean())
    print(
        f"\nper descriptor: {np.mean(in_support):.0f} surface voxels in the support, "
        f"{np.mean(non_empty):.0f} of {soft[0].shape[1]} bins non-empty (soft votes)"
    )
    print(f"load average at the end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}; soft-vote kernel: "
          f"{'numba' if use_numba() else 'numpy'} (VOXPOSE_KERNELS)")  # fmt: skip


if __name__ == "__main__":
    main()
