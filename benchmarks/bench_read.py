"""Reading a voxpose HDF5 file: decoded once and checked on those arrays, against checked then read again (issue 22).

Usage: ``python benchmarks/bench_read.py FILE.h5 [FILE.h5 ...] [--repeats N]`` (e.g. a run's descriptor files).

``open_layout`` decodes every dataset once and computes the content checksum on the decoded arrays
(``voxpose.io.hdf5.Contents``). Before, it hashed the file by decoding every dataset, and the reader then decoded
them again; that path is what ``checksum.damage(f)`` followed by a full read still does, so both are timed on the
same files (best of ``--repeats``), with the file's size and compression.

Measured (c183b2d's reader, a default run on both cores beside it): spiral_gen_03's descriptors (418 frames) as
gzip (an older run's file) 0.497 s twice against 0.329 once, as LZF (c183b2d) 0.276 against 0.227; so a
descriptor file is read 2.2x faster than before (0.497 -> 0.227 s); its voxel and motion files 0.17-0.19 and
0.025 s either way (small datasets).
"""

import argparse
import os
import time

import h5py

from voxpose.io.checksum import damage
from voxpose.io.hdf5 import open_layout


def _twice(path) -> None:
    """The former reader: checksum by decoding, then every dataset decoded again."""
    with h5py.File(path, "r") as f:
        assert damage(f) is None
        f.visititems(lambda name, obj: obj[()] if isinstance(obj, h5py.Dataset) else None)


def _once(path) -> None:
    with h5py.File(path, "r") as f:
        layout = f.attrs["layout"]
    open_layout(path, layout.decode() if isinstance(layout, bytes) else layout)


def best(function, path, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function(path)
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print(f"{'file':40s} {'MB':>6s} {'compression':>11s} {'twice s':>8s} {'once s':>7s} {'ratio':>6s}")
    total_twice = total_once = 0.0
    for path in args.files:
        with h5py.File(path, "r") as f:
            kinds = sorted({obj.compression or "none" for obj in f.values() if isinstance(obj, h5py.Dataset)})
        size = os.path.getsize(path) / 1e6
        twice, once = best(_twice, path, args.repeats), best(_once, path, args.repeats)
        total_twice, total_once = total_twice + twice, total_once + once
        print(f"{str(path)[-40:]:40s} {size:6.1f} {'/'.join(kinds):>11s} {twice:8.3f} {once:7.3f} {twice / once:6.2f}")
    print(f"{'total':40s} {'':6s} {'':>11s} {total_twice:8.3f} {total_once:7.3f} {total_twice / total_once:6.2f}")


if __name__ == "__main__":
    main()
