"""Cost of body-frame 3D shape contexts (``descriptor.frame: body``) against the world frame, on a voxel file.

    python benchmarks/bench_body_frame.py results/voxels/circle6/spiral_gen_03.h5 [--frames 60] [--repeats 3]

Both frames go through ``describe_sequence`` on the same frames, interleaved, in one process; process CPU time per
frame (minimum over repeats) and the ratio are printed. The body frame adds the reference heading, the resampling
on the turned grid, its surface and basis voxels (``voxpose.descriptors.body_frame``); the lookup-table path is
the same. Measured on the default spiral_gen_03 (40 frames, 2 repeats, load average 9 on 2 cores): world 6.8
ms/frame, body 12.3 ms/frame, ratio 1.81. With the grid resampled column by column (2026-11-27, 60 frames, 3
repeats, ``taskset -c 1``, a default run on the other core, old and new main alternating twice): body 11.5 / 10.1
-> 8.0 / 6.9 ms/frame, world 4.7 / 5.2 ms/frame.
"""

import argparse
import time

import numpy as np

from voxpose.descriptors.sequence import describe_sequence
from voxpose.descriptors.settings import DescriptorSettings
from voxpose.voxels.sequence import VoxelSequence, read_voxels


def first_frames(seq: VoxelSequence, n: int) -> VoxelSequence:
    n = min(n, seq.n_frames)
    a, b = seq.offsets[n], seq.basis_offsets[n]
    return VoxelSequence(l_res=seq.l_res, h_sub=seq.h_sub, h_sub_frame=seq.h_sub_frame, ijk=seq.ijk[:a],
                         offsets=seq.offsets[: n + 1], surface=seq.surface[:a], basis=seq.basis[:b],
                         basis_offsets=seq.basis_offsets[: n + 1], empty=seq.empty[:n],
                         shifts=seq.shifts[:n])  # fmt: skip


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("voxels")
    p.add_argument("--frames", type=int, default=60)
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    seq = first_frames(read_voxels(args.voxels)[0], args.frames)
    n_basis = int(np.median(np.diff(seq.basis_offsets)))
    times = {"world": [], "body": []}
    for _ in range(args.repeats):
        for frame in times:
            start = time.process_time()
            describe_sequence(seq, DescriptorSettings(frame=frame), n_basis=n_basis)
            times[frame].append((time.process_time() - start) / seq.n_frames)
    world, body = min(times["world"]), min(times["body"])
    print(f"{seq.n_frames} frames: world {1000 * world:.1f} ms/frame, body {1000 * body:.1f} ms/frame, "
          f"ratio {body / world:.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
