"""HDF5 layouts: round trips, atomic writes, clear errors for the wrong or a damaged file."""

import signal
import subprocess
import sys

import h5py
import numpy as np
import pytest

from voxpose.descriptors.file import read_descriptors, write_descriptors
from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path
from voxpose.io.hdf5 import read_arrays, write_arrays
from voxpose.motion.data import MotionData, read_motion, write_motion


def _motion(n=5):
    rng = np.random.default_rng(0)
    return MotionData(
        name="walk_x",
        kind="walk",
        fps=30.0,
        positions=rng.normal(size=(n, 14, 3)),
        rotations=np.tile(np.eye(3), (n, 14, 1, 1)),
        angles=rng.normal(size=(n, 42)),
        ends=rng.normal(size=(n, 5, 3)),
        offsets=rng.normal(size=(14, 3)),
        height=1.75,
        source={"path": "walk_x.bvh", "unit": 0.01},
    )


def test_motion_round_trip(tmp_path):
    m = _motion()
    write_motion(tmp_path / "m.h5", m)
    back = read_motion(tmp_path / "m.h5")
    for key in ("positions", "rotations", "angles", "ends", "offsets"):
        assert np.array_equal(getattr(back, key), getattr(m, key))
    assert (back.name, back.kind, back.fps, back.height, back.source) == (m.name, m.kind, m.fps, m.height, m.source)


def test_atomic_path_leaves_nothing_on_error(tmp_path):
    with pytest.raises(RuntimeError), atomic_path(tmp_path / "out.h5") as tmp:
        tmp.write_text("partial")
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


def test_descriptors_round_trip_ragged(tmp_path):
    rng = np.random.default_rng(1)
    desc = [rng.random((n, 8)) for n in (3, 0, 5)]
    ijk = [rng.integers(0, 9, (n, 3)) for n in (3, 0, 5)]
    write_descriptors(tmp_path / "d.h5", desc, ijk, {"n_r": 2})
    d2, i2, meta = read_descriptors(tmp_path / "d.h5")
    assert [len(d) for d in d2] == [3, 0, 5]
    assert all(np.allclose(a, b, rtol=1e-6) for a, b in zip(desc, d2, strict=True))
    assert all(np.array_equal(a, b) for a, b in zip(ijk, i2, strict=True))
    assert meta == {"n_r": 2}


def test_wrong_layout_and_version_and_damage_are_clear(tmp_path):
    write_arrays(tmp_path / "a.h5", "mppca", {"w": np.ones(3)}, {})
    with pytest.raises(VoxposeError, match=r"a.h5: expected a voxpose kmeans file, found mppca"):
        read_arrays(tmp_path / "a.h5", "kmeans")
    with h5py.File(tmp_path / "a.h5", "r+") as f:
        f.attrs["version"] = 99
    with pytest.raises(VoxposeError, match="layout version 99"):
        read_arrays(tmp_path / "a.h5", "mppca")
    (tmp_path / "bad.h5").write_bytes(b"not hdf5 at all")
    with pytest.raises(VoxposeError, match=r"bad.h5: cannot read mppca file"):
        read_arrays(tmp_path / "bad.h5", "mppca")


def test_a_killed_write_leaves_a_temporary_file_that_the_next_write_removes(tmp_path):
    """SIGKILL in the middle of a write (as a cluster's time limit does): the rerun deletes what it left."""
    target = tmp_path / "out.h5"
    code = (
        "import sys, time\nfrom voxpose.io.atomic import atomic_path\n"
        f"with atomic_path({str(target)!r}) as tmp:\n    tmp.write_bytes(b'partial')\n    print('ready', flush=True)\n"
        "    time.sleep(60)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "ready"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    left = [p.name for p in tmp_path.iterdir()]
    assert len(left) == 1 and left[0].startswith(".out.h5.") and left[0].endswith(".tmp")
    (tmp_path / ".other.h5.abcdefgh.tmp").write_bytes(b"another target's")  # not this target's: kept
    (tmp_path / ".out.h5.x.h5.abcdefgh.tmp").write_bytes(b"another target's")
    write_arrays(target, "test", {"x": np.arange(3.0)}, {})
    assert sorted(p.name for p in tmp_path.iterdir()) == [".other.h5.abcdefgh.tmp", ".out.h5.x.h5.abcdefgh.tmp",
                                                         "out.h5"]  # fmt: skip


def test_a_motion_of_no_frames_is_neither_written_nor_read(tmp_path):
    """voxelize and silhouette-contexts failed with a reshape traceback on a 0-frame motion file."""
    empty = _motion(0)
    with pytest.raises(VoxposeError, match="has no frames"):
        write_motion(tmp_path / "m.h5", empty)
    assert list(tmp_path.iterdir()) == []

    class Unchecked(MotionData):  # an older writer's file: through the writer, past its check
        n_frames = 1

    write_motion(tmp_path / "m.h5", Unchecked(**vars(empty)))
    with pytest.raises(VoxposeError, match=rf"^{tmp_path / 'm.h5'}: the motion file has no frames"):
        read_motion(tmp_path / "m.h5")


@pytest.mark.parametrize("n_rows", [0, 1, 3000, 9000])
def test_ragged_arrays_are_chunked_by_whole_rows_and_round_trip(tmp_path, n_rows):
    """Descriptor files' chunks span every column (a row is read from one chunk), hold about 1 MiB (whole rows,
    never more rows than there are), are stored uncompressed as float32 and int32, and the values round-trip
    (float64 descriptors as their float32 rounding), an empty file's too."""
    rng = np.random.default_rng(n_rows)
    cuts = np.sort(rng.integers(0, n_rows + 1, size=4))
    rows, ijk = rng.random((n_rows, 200)), rng.integers(0, 50, (n_rows, 3))
    frames = np.split(rows, cuts)
    write_descriptors(tmp_path / "d.h5", frames, np.split(ijk, cuts), {"n": n_rows})
    with h5py.File(tmp_path / "d.h5") as f:
        chunks, ijk_chunks = f["descriptors"].chunks, f["basis_ijk"].chunks
        assert f["descriptors"].compression is None and f["basis_ijk"].compression is None
        assert (f["descriptors"].dtype, f["basis_ijk"].dtype) == (np.float32, np.int32)
    if n_rows:
        assert chunks == (min(n_rows, 2**20 // (200 * 4)), 200)  # float32 rows of 800 bytes
        assert ijk_chunks == (min(n_rows, 2**20 // 12), 3)
    read, basis, _ = read_descriptors(tmp_path / "d.h5")
    for got, want in zip(read, frames, strict=True):
        np.testing.assert_array_equal(got, want.astype(np.float32))
    for got, want in zip(basis, np.split(ijk, cuts), strict=True):
        np.testing.assert_array_equal(got, want)
