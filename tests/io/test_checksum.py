"""Content checksums: a damaged HDF5 cache (flipped bytes in a compressed block, truncation, an edited frame
boundary, an unfinished file) is refused with a one-line error naming it; an intact one reads back unchanged."""

import h5py
import numpy as np
import pytest

from voxpose.descriptors.file import read_descriptors, write_descriptors
from voxpose.errors import VoxposeError
from voxpose.io.checksum import content_checksum
from voxpose.io.hdf5 import file_damage, read_arrays, write_arrays
from voxpose.voxels.sequence import VoxelSequence, read_voxels, write_voxels


def _descriptors(path, frames=(40, 0, 55, 31)):
    rng = np.random.default_rng(3)
    desc = [rng.random((n, 100)) for n in frames]
    ijk = [rng.integers(0, 60, (n, 3)) for n in frames]
    write_descriptors(path, desc, ijk, {"n_r": 2})
    return desc


def _voxels(path, n_frames=6):
    rng = np.random.default_rng(4)
    counts = rng.integers(300, 500, n_frames)
    offsets = np.concatenate([[0], np.cumsum(counts)])
    seq = VoxelSequence(
        l_res=0.03, h_sub=1.7, h_sub_frame=0, ijk=rng.integers(0, 60, (offsets[-1], 3)).astype(np.int32),
        offsets=offsets, surface=rng.random(offsets[-1]) < 0.3, basis=np.zeros(0, np.int32),
        basis_offsets=np.zeros(n_frames + 1, np.int64), empty=np.zeros(n_frames, bool), shifts=np.zeros((n_frames, 3)),
    )  # fmt: skip
    write_voxels(path, seq, {"rig": "r"})


def _flip_bytes(path, dataset, count=16):
    """Invert ``count`` bytes in the middle of the first stored (compressed) chunk of ``dataset``, where gzip
    notices; return the chunk's byte range."""
    with h5py.File(path, "r") as f:
        ds = f[dataset]
        assert ds.compression == "gzip"
        info = ds.id.get_chunk_info(0)
    start = info.byte_offset + info.size // 2 - count // 2
    data = bytearray(path.read_bytes())
    data[start : start + count] = bytes(b ^ 0xFF for b in data[start : start + count])
    path.write_bytes(bytes(data))


def test_intact_files_read_back_and_checksum_ignores_compression(tmp_path):
    desc = _descriptors(tmp_path / "d.h5")
    back, _, _ = read_descriptors(tmp_path / "d.h5")
    assert all(np.allclose(a, b, rtol=1e-6) for a, b in zip(desc, back, strict=True))
    assert file_damage(tmp_path / "d.h5") is None
    # the same content stored with and without compression has the same checksum
    values = np.arange(5000.0)
    for name, compression in (("a.h5", None), ("b.h5", "gzip")):
        with h5py.File(tmp_path / name, "w") as f:
            f.create_dataset("x", data=values, compression=compression)
    with h5py.File(tmp_path / "a.h5") as a, h5py.File(tmp_path / "b.h5") as b:
        assert content_checksum(a) == content_checksum(b)


@pytest.mark.parametrize("what", ["descriptors", "voxels"])
def test_flipped_bytes_in_a_compressed_block_are_one_line_errors(tmp_path, what):
    path = tmp_path / f"{what}.h5"
    if what == "descriptors":
        _descriptors(path)
        _flip_bytes(path, "descriptors")
        read = read_descriptors
    else:
        _voxels(path)
        _flip_bytes(path, "ijk")
        read = read_voxels
    with pytest.raises(VoxposeError, match=rf"{what}.h5: damaged {what} file: ") as err:
        read(path)
    assert "\n" not in str(err.value)
    assert file_damage(path) is not None


def test_an_edited_frame_boundary_is_refused(tmp_path):
    path = tmp_path / "d.h5"
    _descriptors(path)
    with h5py.File(path, "r") as f:
        offsets = f["descriptors_offsets"][()]
        at = f["descriptors_offsets"].id.get_offset() + 2 * 8  # the boundary between frames 1 and 2 (int64)
    assert offsets[2] == 40
    data = bytearray(path.read_bytes())
    data[at : at + 8] = np.int64(30).tobytes()  # frame 1 now steals 10 rows of frame 0: still a valid-looking file
    path.write_bytes(bytes(data))
    with h5py.File(path, "r") as f:
        assert f["descriptors_offsets"][2] == 30
    with pytest.raises(VoxposeError, match=r"d.h5: damaged descriptors file: content does not match its checksum"):
        read_descriptors(path)


def test_a_truncated_file_is_refused_by_name(tmp_path):
    path = tmp_path / "d.h5"
    _descriptors(path)
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(VoxposeError, match=r"d.h5: cannot read descriptors file"):
        read_descriptors(path)
    assert file_damage(path).startswith("not a readable HDF5 file")


def test_a_file_without_its_checksum_is_unfinished(tmp_path):
    path = tmp_path / "a.h5"
    write_arrays(path, "mppca", {"w": np.ones(3)}, {})
    assert read_arrays(path, "mppca")[0]["w"].tolist() == [1, 1, 1]
    with h5py.File(path, "r+") as f:
        del f.attrs["checksum"]
    with pytest.raises(VoxposeError, match=r"a.h5: damaged mppca file: no checksum"):
        read_arrays(path, "mppca")


def test_an_edited_attribute_is_refused(tmp_path):
    path = tmp_path / "a.h5"
    write_arrays(path, "mppca", {"w": np.ones(3)}, {"K": 16})
    with h5py.File(path, "r+") as f:
        f.attrs["meta"] = '{"K": 17}'
    with pytest.raises(VoxposeError, match="content does not match its checksum"):
        read_arrays(path, "mppca")
