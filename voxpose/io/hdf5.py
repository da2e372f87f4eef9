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
from voxpose.io.checksum import damage, seal

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


def open_layout(path, layout: str, check=None):
    """Open a voxpose file of layout ``layout`` for reading: its layout name and version, then ``check(attrs)``
    (a format version a reader checks before anything else), then its content checksum. A file that fails any
    of them is a one-line error naming it."""
    f = open_file(path, layout)
    try:
        check_layout(f, path, layout)
        if check is not None:
            check(f.attrs)
        reason = damage(f)
        if reason is not None:
            raise VoxposeError(f"{path}: damaged {layout} file: {reason}; `voxpose verify --remove` deletes it, "
                               "and the next snakemake run makes it again")  # fmt: skip
    except BaseException:
        f.close()
        raise
    return f


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


def write_ragged(f, name: str, parts, dtype) -> None:
    offsets = np.zeros(len(parts) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([len(p) for p in parts])
    rows = np.concatenate(parts).astype(dtype) if len(parts) else np.zeros((0,), dtype)
    f.create_dataset(name, data=rows, compression="gzip", chunks=True if rows.size else None)
    f.create_dataset(f"{name}_offsets", data=offsets)


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
