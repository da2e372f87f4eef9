"""HDF5 files of voxpose: a layout name and version on every file, JSON metadata, and the generic layouts.

Each stage's typed layout (motions, voxels, descriptors) lives with its data type and is built from these
pieces; every writer goes through ``voxpose.io.atomic.atomic_path`` and ``new_file`` (which seals the file with
its content checksum, ``voxpose.io.checksum``), every reader through ``open_layout`` (which verifies it).
"""

import contextlib
import json

import h5py
import numpy as np

from voxpose import __version__
from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path
from voxpose.io.checksum import READ_ERRORS, damage, seal, unreadable

LAYOUT_VERSION = 1


def write_meta(f, meta: dict) -> None:
    """Small metadata as one JSON attribute (names, parameters, provenance)."""
    f.attrs["meta"] = json.dumps(meta)


def read_meta(f) -> dict:
    return json.loads(f.attrs["meta"])


def open_file(path, what: str):
    """Open an HDF5 file for reading, turning a missing or unreadable file into a one-line error."""
    try:
        return h5py.File(path, "r")
    except (OSError, FileNotFoundError) as err:
        raise VoxposeError(f"{path}: cannot read {what} file ({err})") from None


def check_layout(f, path, layout: str) -> None:
    found = f.attrs.get("layout")
    found = found.decode() if isinstance(found, bytes) else found
    if found != layout:
        raise VoxposeError(f"{path}: expected a voxpose {layout} file, found {found or 'no voxpose layout'}")
    version = int(f.attrs.get("version", -1))
    if version != LAYOUT_VERSION:
        raise VoxposeError(
            f"{path}: {layout} file of layout version {version}, this voxpose reads version {LAYOUT_VERSION}"
        )


class Contents:
    """A voxpose file read whole into memory by ``open_layout``: every dataset decoded once, as a numpy array
    (its checksum is verified on those arrays, not on a second decode: on descriptor files reading twice took
    as long as the rest of ``voxpose features``), and the attributes of every group. Read like the h5py file it
    came from: ``f[name]`` (a dataset's array, or a group's ``Contents``; "a/b" paths too), ``name in f``,
    ``f.items()``, ``f.attrs``, ``with f``."""

    def __init__(self, values: dict, attrs: dict, prefix: str = ""):
        self._values, self._attrs, self._prefix = values, attrs, prefix  # both keyed by full name ("" the root)
        self.attrs = attrs[prefix]
        names = [name for name in (*values, *attrs) if name.startswith(prefix) and name != prefix]
        self._keys = sorted({name[len(prefix) :].split("/")[0] for name in names})

    @classmethod
    def read(cls, f) -> "Contents":
        """Everything in the open h5py file ``f``."""
        values, attrs = {}, {"": dict(f.attrs)}

        def take(name, obj):
            if isinstance(obj, h5py.Dataset):
                values[name] = obj[()]
            else:
                attrs[name + "/"] = dict(obj.attrs)

        f.visititems(take)
        return cls(values, attrs)

    @property
    def datasets(self) -> dict:
        """Every dataset's value by its full name (as h5py's ``visit`` names it)."""
        return self._values

    def __getitem__(self, name: str):
        full = self._prefix + name.strip("/")
        if full in self._values:
            return self._values[full]
        if full + "/" in self._attrs:
            return Contents(self._values, self._attrs, full + "/")
        raise KeyError(f"no {name!r} in the file")

    def __contains__(self, name: str) -> bool:
        full = self._prefix + name.strip("/")
        return full in self._values or full + "/" in self._attrs

    def __iter__(self):
        return iter(self._keys)

    def keys(self) -> list:
        return list(self._keys)

    def items(self) -> list:
        return [(key, self[key]) for key in self._keys]

    def __enter__(self) -> "Contents":
        return self

    def __exit__(self, *exc) -> None:
        return None


def open_layout(path, layout: str, check=None) -> Contents:
    """Read a voxpose file of layout ``layout`` whole (``Contents``): its layout name and version are checked,
    then ``check(attrs)`` (a format version a reader checks before anything else), then its content checksum.
    A file that fails any of them is a one-line error naming it."""
    with open_file(path, layout) as f:
        check_layout(f, path, layout)
        if check is not None:
            check(f.attrs)
        try:
            contents = Contents.read(f)
        except READ_ERRORS as err:
            contents, reason = None, unreadable(err)
        if contents is not None:
            reason = damage(f, contents.datasets)
        if reason is not None:
            raise VoxposeError(f"{path}: damaged {layout} file: {reason}; `voxpose verify --remove` deletes it, "
                               "and the next snakemake run makes it again")  # fmt: skip
    return contents


def file_damage(path) -> str | None:
    """Why the voxpose HDF5 file at ``path`` cannot be trusted (a short reason), or None (``voxpose verify``)."""
    try:
        with h5py.File(path, "r") as f:
            return damage(f)
    except OSError as err:
        return f"not a readable HDF5 file ({str(err).splitlines()[0]})"


@contextlib.contextmanager
def new_file(tmp, layout: str):
    """A new voxpose file of layout ``layout`` at ``tmp``; sealed with its content checksum when the block ends
    without an error (the checksum is the last thing written)."""
    with h5py.File(tmp, "w") as f:
        f.attrs["layout"] = layout
        f.attrs["version"] = LAYOUT_VERSION
        f.attrs["voxpose_version"] = __version__
        yield f
        seal(f)


# --- ragged per-frame arrays: rows of all frames concatenated, frame f = rows[offsets[f]:offsets[f+1]] ------

_CHUNK_BYTES = 1 << 20  # HDF5 chunk size of ragged arrays (row_chunks)


def write_ragged(f, name: str, parts, dtype) -> None:
    """Frames' rows concatenated (straight into ``dtype``), stored uncompressed in whole-row chunks.

    The descriptor files are the workflow's largest and each is read several times. LZF (before, c183b2d's
    choice over gzip) made them 27 % smaller but cost every write a compression and a decompression (the checksum
    reads the file back) and every read a decompression: on a default describe job's 175 frames (34,675 x 200
    float32, 27.7 MB) 0.17 s to write and 0.06-0.09 s to read with LZF, 0.02 and 0.01 s without; in a real-data
    features job the reads of its 75 descriptor files took 5.3 s of its 45. Chunks stay whole rows, so a damaged
    file is still refused by its checksum chunk by chunk (``voxpose.io.checksum``)."""
    offsets = np.zeros(len(parts) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([len(p) for p in parts])
    rows = np.concatenate(parts, dtype=dtype) if len(parts) else np.zeros((0,), dtype)
    f.create_dataset(name, data=rows, chunks=row_chunks(rows.shape, rows.dtype.itemsize))
    f.create_dataset(f"{name}_offsets", data=offsets)


def row_chunks(shape: tuple, itemsize: int, target_bytes: int = _CHUNK_BYTES) -> tuple | None:
    """HDF5 chunks of whole rows, about ``target_bytes`` each (None for an empty array: h5py's own choice).

    h5py's automatic chunks of a (56597, 200) float32 descriptor array are (1769, 7): 7 columns wide, so reading
    it whole gathers ~930 chunks column-slab by column-slab. Whole-row chunks read in 0.11 s instead of 0.19 s
    (a 282-frame default motion, 45 MB of descriptors; same values, same file size within 1 %).
    """
    if not np.prod(shape):
        return None
    row_bytes = itemsize * int(np.prod(shape[1:]))
    return (max(1, min(shape[0], target_bytes // row_bytes)), *shape[1:])


def read_ragged(f, name: str) -> list:
    rows = f[name][()]
    offsets = f[f"{name}_offsets"][()]
    return [rows[a:b] for a, b in zip(offsets[:-1], offsets[1:], strict=True)]


# --- generic layouts: flat arrays, named groups, arrays per motion ------------------------------------------


def write_arrays(path, layout: str, arrays: dict, meta: dict) -> None:
    """A flat file of named arrays plus metadata (fitted models: MPPCA, K-means, pose PCA, MVRVM)."""
    with atomic_path(path) as tmp, new_file(tmp, layout) as f:
        for key, value in arrays.items():
            f.create_dataset(key, data=np.asarray(value))
        write_meta(f, meta)


def read_arrays(path, layout: str):
    """-> (dict of arrays, meta) of a file written by ``write_arrays`` with the same layout name."""
    with open_layout(path, layout) as f:
        return {key: f[key][()] for key in f}, read_meta(f)


def write_groups(path, layout: str, groups: dict, meta: dict, attrs: dict | None = None) -> None:
    """Named groups of arrays, each with its own metadata: ``groups[name] = (arrays, meta)`` (bundled models).

    ``attrs`` are extra scalar file attributes (e.g. a format version a reader checks before anything else).
    """
    with atomic_path(path) as tmp, new_file(tmp, layout) as f:
        for key, value in (attrs or {}).items():
            f.attrs[key] = value
        for name, (arrays, group_meta) in groups.items():
            group = f.create_group(name)
            for key, value in arrays.items():
                value = np.asarray(value)
                group.create_dataset(key, data=value, compression="gzip" if value.size > 4096 else None)
            write_meta(group, group_meta)
        write_meta(f, meta)


def read_groups(path, layout: str, check=None):
    """-> ({name: (arrays, meta)}, meta) of a file written by ``write_groups``.

    ``check(attrs)`` runs on the file attributes before anything else is read. A missing piece (a
    damaged or hand-edited file) is a one-line error naming the file.
    """
    with open_layout(path, layout, check) as f:
        try:
            groups = {name: ({k: g[k][()] for k in g}, read_meta(g)) for name, g in f.items()}
            return groups, read_meta(f)
        except (KeyError, OSError, ValueError) as err:
            raise VoxposeError(f"{path}: damaged {layout} file ({err})") from None


def write_per_motion(path, layout: str, motions: dict, meta: dict) -> None:
    """Named arrays per motion: ``motions[name][key]`` -> dataset ``/motions/name/key``."""
    with atomic_path(path) as tmp, new_file(tmp, layout) as f:
        for name, arrays in motions.items():
            group = f.create_group(f"motions/{name}")
            for key, value in arrays.items():
                group.create_dataset(key, data=np.asarray(value), compression="gzip")
        write_meta(f, meta)


def read_per_motion(path, layout: str):
    """-> ({motion: {key: array}}, meta) of a file written by ``write_per_motion``."""
    with open_layout(path, layout) as f:
        motions = {name: {k: g[k][()] for k in g} for name, g in f["motions"].items()}
        return motions, read_meta(f)
