"""Cost of verified reads: reading a workflow cache with its content checksum verified (``open_layout``) against
reading the same arrays with h5py alone, and the cost of ``voxpose verify`` per MB of cache.

Usage: ``python benchmarks/bench_checksum.py FILE.h5 [...]`` (e.g. descriptor files of a finished run); prints
seconds per read (best of 5) and their ratio.
"""

import sys
import time
from pathlib import Path

import h5py

from voxpose.io.checksum import content_checksum
from voxpose.io.hdf5 import file_damage


def _best(fn, repeat=5) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def _read_all(path):
    names = []
    with h5py.File(path, "r") as f:
        f.visit(names.append)
        for name in names:
            if isinstance(f[name], h5py.Dataset):
                f[name][()]


def _checksum(path):
    with h5py.File(path, "r") as f:
        content_checksum(f)


def main(paths) -> None:
    print(f"{'file':60s} {'MB':>6s} {'read s':>8s} {'checksum s':>10s} {'ratio':>6s}")
    for path in map(Path, paths):
        assert file_damage(path) is None, path
        read, check = _best(lambda p=path: _read_all(p)), _best(lambda p=path: _checksum(p))
        mb = path.stat().st_size / 2**20
        print(f"{str(path)[-60:]:60s} {mb:6.2f} {read:8.4f} {check:10.4f} {check / read:6.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
