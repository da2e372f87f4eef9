"""Load every shared BVH file with ``load_motion`` and print timings, frames per motion type and heights.

Usage: ``python benchmarks/bench_load_bvh.py [BVH_DIR]`` (default: ../shared/data/bvh beside the repo).
"""

import sys
import time
from collections import defaultdict
from pathlib import Path

from voxpose.io.bvh import read_bvh
from voxpose.motion.load import load_motion


def main(folder: Path) -> None:
    files = sorted(folder.glob("*.bvh"))
    if not files:
        sys.exit(f"no .bvh files in {folder}")
    frames, seconds, heights = defaultdict(int), defaultdict(float), defaultdict(list)
    parse_total = load_total = 0.0
    source_frames = 0
    print(
        f"{'file':50s} {'skeleton':9s} {'src frames':>10s} {'fps':>5s} {'out':>5s} {'height m':>8s} "
        f"{'parse ms':>8s} {'load ms':>8s}"
    )
    for path in files:
        t0 = time.perf_counter()
        bvh = read_bvh(path)
        t1 = time.perf_counter()
        m = load_motion(path)
        t2 = time.perf_counter()
        parse_total += t1 - t0
        load_total += t2 - t1
        source_frames += bvh.n_frames
        frames[m.kind] += m.n_frames
        seconds[m.kind] += m.n_frames / m.fps
        heights[m.source["skeleton"]].append(m.height)
        print(
            f"{path.name:50s} {m.source['skeleton']:9s} {bvh.n_frames:10d} {m.source['source_fps']:5.0f} "
            f"{m.n_frames:5d} {m.height:8.3f} {1e3 * (t1 - t0):8.1f} {1e3 * (t2 - t1):8.1f}"
        )
    print()
    print(
        f"{len(files)} files, {source_frames} source frames: load_motion {load_total:.2f} s in total "
        f"({1e3 * load_total / len(files):.1f} ms per file, {1e6 * load_total / source_frames:.0f} us per "
        f"source frame); parsing alone {parse_total:.2f} s ({100 * parse_total / load_total:.0f}% of it)"
    )
    print()
    print("frames per type at 30 fps (after dropping reference frames and resampling):")
    for kind in sorted(frames):
        print(f"  {kind:14s} {frames[kind]:6d} frames  {seconds[kind]:6.1f} s")
    print(f"  {'all':14s} {sum(frames.values()):6d} frames  {sum(seconds.values()):6.1f} s")
    print()
    print("standing heights (m):")
    for skeleton, values in sorted(heights.items()):
        print(f"  {skeleton:9s} n={len(values):2d}  min {min(values):.3f}  max {max(values):.3f}")


if __name__ == "__main__":
    default = Path(__file__).resolve().parents[1].parent / "shared/data/bvh"
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else default)
