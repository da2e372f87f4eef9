"""Content checksums of HDF5 files: every file voxpose writes carries a SHA-256 of what it holds, and every read
verifies it, so a damaged cache (flipped bytes, a truncated file, an edited entry) is refused by name instead of
being read as wrong numbers or failing deep inside HDF5.

The checksum covers every group, dataset and attribute (names, dtypes, shapes and values, in sorted order) except
the ``checksum`` attribute itself, which is written last, after all the data: a file without it was never finished.
It is computed from the decoded values, so it does not depend on the compression a dataset happens to use.
"""

import hashlib

import h5py
import numpy as np

ATTRIBUTE = "checksum"
_BLOCK_BYTES = 1 << 24  # datasets are hashed in row blocks of about this size: memory stays bounded


def _raw(arr: np.ndarray) -> np.ndarray:
    """The bytes ``arr.tobytes()`` returns, as a flat uint8 view (no copy for a C-contiguous array): hashing
    ``tobytes`` copied every block first, which halved the hash's speed (80 MB of float32: 0.045 s hashed directly,
    0.094 - 0.156 s through ``tobytes``)."""
    return np.ascontiguousarray(arr).reshape(-1).view(np.uint8)


def _update_value(h, value) -> None:
    if isinstance(value, str):
        value = value.encode()
    if isinstance(value, bytes):
        h.update(b"b%d:" % len(value) + value)
        return
    arr = np.asarray(value)
    h.update(f"a{arr.dtype.str}{arr.shape}:".encode())
    if arr.dtype.kind == "O":  # variable-length strings: hash each element's bytes, never object pointers
        for item in arr.ravel():
            _update_value(h, item)
    else:
        h.update(_raw(arr))


def _update_dataset(h, ds, value=None) -> None:
    """Hash a dataset in row blocks; ``value``, when given, is what was read from it, hashed instead."""
    h.update(f"d{ds.dtype.str}{ds.shape}:".encode())
    if ds.shape is None or ds.ndim == 0:
        _update_value(h, ds[()] if value is None else value)
        return
    rows = ds if value is None else value
    row_bytes = max(1, ds.dtype.itemsize * int(np.prod(ds.shape[1:], dtype=np.int64)))
    step = max(1, _BLOCK_BYTES // row_bytes)
    for start in range(0, ds.shape[0], step):
        block = rows[start : start + step]
        if block.dtype.kind == "O":
            _update_value(h, block)
        else:
            h.update(_raw(block))


def _update_attrs(h, obj, skip=()) -> None:
    for key in sorted(obj.attrs):
        if key not in skip:
            h.update(f"@{key}=".encode())
            _update_value(h, obj.attrs[key])


def content_checksum(f, decoded=None) -> str:
    """``sha256:<hex>`` of everything in the open HDF5 file ``f`` but its own ``checksum`` attribute.

    ``decoded`` (optional) maps dataset names to their values already read from ``f`` (``hdf5.Contents``):
    those arrays are hashed instead of being decoded a second time, in the same row blocks, so the checksum is
    the same. Reading damaged data raises what h5py raises (``OSError``, ``KeyError``, ``ValueError``);
    ``damage`` turns that into a reason."""
    h = hashlib.sha256()
    _update_attrs(h, f, skip=(ATTRIBUTE,))
    names = []
    f.visit(names.append)
    for name in sorted(names):
        obj = f[name]
        h.update(f"\n{name}:".encode())
        if isinstance(obj, h5py.Dataset):
            _update_dataset(h, obj, None if decoded is None else decoded[name])
        _update_attrs(h, obj)
    return "sha256:" + h.hexdigest()


def seal(f) -> None:
    """Record the checksum of ``f``'s content (open for writing), after everything else is written."""
    f.flush()
    f.attrs[ATTRIBUTE] = content_checksum(f)


READ_ERRORS = (OSError, KeyError, ValueError, RuntimeError)
"""What h5py raises on data it cannot decode."""


def unreadable(err: Exception) -> str:
    """The short reason for data h5py could not decode."""
    return f"unreadable data ({str(err).splitlines()[0] if str(err) else type(err).__name__})"


def damage(f, decoded=None) -> str | None:
    """Why the open HDF5 file ``f`` does not hold what was written (a short reason), or None when it does;
    ``decoded`` as in ``content_checksum``."""
    recorded = f.attrs.get(ATTRIBUTE)
    if recorded is None:
        return "no checksum (never finished, or written by a voxpose before checksums)"
    recorded = recorded.decode() if isinstance(recorded, bytes) else str(recorded)
    try:
        found = content_checksum(f, decoded)
    except READ_ERRORS as err:
        return unreadable(err)
    if found != recorded:
        return "content does not match its checksum"
    return None
