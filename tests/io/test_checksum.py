"""Content checksums: a damaged HDF5 cache (flipped bytes in a stored chunk, truncation, an edited frame
boundary, an unfinished file) is refused with a one-line error naming it; an intact one reads back unchanged."""

import h5py
import numpy as np
import pytest

from voxpose.descriptors.file import descriptor_headings, read_descriptor_file, read_descriptors, write_descriptors
from voxpose.errors import VoxposeError
from voxpose.io.checksum import content_checksum, seal
from voxpose.io.hdf5 import LAYOUT_VERSION, Contents, file_damage, open_layout, read_arrays, write_arrays
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
    """Invert ``count`` bytes in the middle of the first stored chunk of ``dataset``: the decoder fails (gzip) or
    the chunk holds other values (uncompressed), which the checksum refuses."""
    with h5py.File(path, "r") as f:
        ds = f[dataset]
        assert ds.compression in ("gzip", None)
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
def test_flipped_bytes_in_a_stored_chunk_are_one_line_errors(tmp_path, what):
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


def _mixed_file(path):
    """Groups, a vlen-string array, a scalar, an empty array and a float array spanning several hash blocks."""
    with h5py.File(path, "w") as f:
        f.attrs["meta"] = "{}"
        f.create_dataset("big", data=np.arange(3 * (1 << 21), dtype=np.float64).reshape(-1, 2), compression="gzip")
        f.create_dataset("names", data=np.array(["walk", "jump"], dtype=object), dtype=h5py.string_dtype())
        f.create_dataset("scalar", data=2.5)
        group = f.create_group("motions/walk")
        group.attrs["meta"] = '{"n": 1}'
        group.create_dataset("empty", data=np.zeros((0, 3)))


def test_the_checksum_of_decoded_arrays_is_the_files(tmp_path):
    """``open_layout`` hashes the arrays it decoded rather than decoding twice: the same checksum as from the
    file (block by block, strings and scalars included), and a changed array gives another one."""
    path = tmp_path / "m.h5"
    _mixed_file(path)
    with h5py.File(path, "r") as f:
        contents = Contents.read(f)
        assert contents["big"].nbytes > 2 * (1 << 24)  # more than two of the checksum's row blocks
        assert content_checksum(f, contents.datasets) == content_checksum(f)
        contents.datasets["big"][7, 1] += 1.0
        assert content_checksum(f, contents.datasets) != content_checksum(f)


def test_the_checksum_of_a_fixed_file_is_unchanged(tmp_path):
    """Every file written so far carries a checksum that must still verify: the digest of a fixed file (several
    hash blocks, float32/int32/bool/big-endian/empty/scalar/string datasets, array and string attributes) is the
    one the hashing through ``tobytes`` gave (a703831), from the file and from the
    decoded arrays."""
    path = tmp_path / "m.h5"
    _mixed_file(path)
    with h5py.File(path, "a") as f:
        f.create_dataset("f32", data=np.linspace(-1, 1, 600, dtype=np.float32).reshape(3, 200))
        f.create_dataset("i32", data=np.arange(-6, 6, dtype=np.int32).reshape(4, 3))
        f.create_dataset("flags", data=np.array([True, False, True]))
        f.create_dataset("be", data=np.arange(5, dtype=">i8"))
        f["f32"].attrs["heading"] = np.array([0.5, 90.0])
    digest = "sha256:6c24b89bd7c9da5f5a96dcef7b1fb831d9adc4a15ffbc31d87e254b03c841970"
    with h5py.File(path, "r") as f:
        assert content_checksum(f) == digest
        assert content_checksum(f, Contents.read(f).datasets) == digest


def test_open_layout_decodes_every_dataset_once_and_reads_like_the_file(tmp_path, monkeypatch):
    path = tmp_path / "m.h5"
    _mixed_file(path)
    with h5py.File(path, "r+") as f:
        f.attrs["layout"], f.attrs["version"] = "mixed", LAYOUT_VERSION
        seal(f)
    reads = []
    original = h5py.Dataset.__getitem__

    def counted(ds, key):
        reads.append(ds.name)
        return original(ds, key)

    monkeypatch.setattr(h5py.Dataset, "__getitem__", counted)
    with open_layout(path, "mixed") as f:
        assert sorted(reads) == ["/big", "/motions/walk/empty", "/names", "/scalar"]
        assert sorted(f) == ["big", "motions", "names", "scalar"] and "motions/walk" in f and "nothing" not in f
        assert [name for name, _ in f["motions"].items()] == ["walk"]
        assert f["motions/walk"].attrs["meta"] == '{"n": 1}' and f["motions"]["walk"]["empty"].shape == (0, 3)
        assert f["big"][()].shape == (3 << 20, 2) and f["big"][5, 1] == 11.0 and f["scalar"] == 2.5
        assert [bytes(n).decode() for n in f["names"]] == ["walk", "jump"]
        with pytest.raises(KeyError):
            f["nothing"]


def test_a_descriptor_file_is_read_whole_once_and_its_headings_alone_without_the_descriptors(tmp_path):
    path = tmp_path / "d.h5"
    rng = np.random.default_rng(5)
    desc = [rng.random((n, 20)) for n in (4, 0, 3)]
    ijk = [rng.integers(0, 60, (n, 3)) for n in (4, 0, 3)]
    write_descriptors(path, desc, ijk, {"motion": "walk"}, reference_heading=[10.0, 200.0, 355.5])
    read = read_descriptor_file(path)
    assert read.reference_heading.tolist() == [10.0, 200.0, 355.5] and read.meta == {"motion": "walk"}
    assert [len(d) for d in read.frames] == [4, 0, 3] and np.allclose(read.frames[2], desc[2], rtol=1e-6)
    heading, meta = descriptor_headings(path)
    assert heading.tolist() == [10.0, 200.0, 355.5] and meta == {"motion": "walk"}
    write_descriptors(path, desc, ijk, {"motion": "walk"})  # world frame: no reference heading
    assert read_descriptor_file(path).reference_heading is None and descriptor_headings(path)[0] is None
