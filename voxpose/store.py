"""On-disk layouts (HDF5) of every stage, and atomic writes: one place for both.

Every file is written to a temporary name beside its target and renamed into place only when complete,
so an interrupted or failed job never leaves a partial output behind.
"""

import contextlib
import json
import os
import tempfile
from pathlib import Path

import h5py
import numpy as np

from . import __version__
from .errors import VoxposeError
from .motion_data import MotionData

LAYOUT_VERSION = 1


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; rename it to ``path`` on success, delete it on error."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp = Path(tmp)
    try:
        yield tmp
        umask = os.umask(0)
        os.umask(umask)
        tmp.chmod(0o666 & ~umask)  # mkstemp creates 0600; give the file the usual permissions
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _write_meta(f, meta: dict) -> None:
    """Small metadata as one JSON attribute (names, parameters, provenance)."""
    f.attrs["meta"] = json.dumps(meta)


def _read_meta(f) -> dict:
    return json.loads(f.attrs["meta"])


def _open(path, what: str):
    """Open an HDF5 file for reading, turning a missing or damaged file into a one-line error."""
    try:
        return h5py.File(path, "r")
    except (OSError, FileNotFoundError) as err:
        raise VoxposeError(f"{path}: cannot read {what} file ({err})") from None


def _check_layout(f, path, layout: str) -> None:
    found = f.attrs.get("layout")
    found = found.decode() if isinstance(found, bytes) else found
    if found != layout:
        raise VoxposeError(f"{path}: expected a voxpose {layout} file, found {found or 'no voxpose layout'}")
    version = int(f.attrs.get("version", -1))
    if version != LAYOUT_VERSION:
        raise VoxposeError(
            f"{path}: {layout} file of layout version {version}, this voxpose reads version {LAYOUT_VERSION}"
        )


def _new(tmp, layout: str):
    f = h5py.File(tmp, "w")
    f.attrs["layout"] = layout
    f.attrs["version"] = LAYOUT_VERSION
    f.attrs["voxpose_version"] = __version__
    return f


# --- motions/{motion}.h5: canonical poses (Section 2) -------------------------------------------------------


def write_motion(path, motion: MotionData) -> None:
    """One motion's canonical poses, joint positions, end points and skeleton offsets."""
    with atomic_path(path) as tmp, _new(tmp, "motion") as f:
        for key in ("positions", "rotations", "angles", "ends"):
            f.create_dataset(key, data=getattr(motion, key), compression="gzip", chunks=True)
        f.create_dataset("offsets", data=motion.offsets)
        meta = {"name": motion.name, "kind": motion.kind, "fps": motion.fps, "height": motion.height}
        _write_meta(f, meta | {"source": motion.source})


def read_motion(path) -> MotionData:
    with _open(path, "motion") as f:
        _check_layout(f, path, "motion")
        meta = _read_meta(f)
        return MotionData(
            name=meta["name"],
            kind=meta["kind"],
            fps=float(meta["fps"]),
            positions=f["positions"][()],
            rotations=f["rotations"][()],
            angles=f["angles"][()],
            ends=f["ends"][()],
            offsets=f["offsets"][()],
            height=float(meta["height"]),
            source=meta["source"],
        )


# --- ragged per-frame arrays: rows of all frames concatenated, frame f = rows[offsets[f]:offsets[f+1]] ------


def _write_ragged(f, name: str, parts, dtype) -> None:
    offsets = np.zeros(len(parts) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([len(p) for p in parts])
    rows = np.concatenate(parts).astype(dtype) if len(parts) else np.zeros((0,), dtype)
    f.create_dataset(name, data=rows, compression="gzip", chunks=True if rows.size else None)
    f.create_dataset(f"{name}_offsets", data=offsets)


def _read_ragged(f, name: str) -> list:
    rows = f[name][()]
    offsets = f[f"{name}_offsets"][()]
    return [rows[a:b] for a, b in zip(offsets[:-1], offsets[1:], strict=True)]


# --- descriptors/{rig}/{desc}/{motion}.h5: 3D shape contexts per frame (Section 4) -----------------------


def write_descriptors(path, descriptors: list, basis_ijk: list, meta: dict) -> None:
    """Per frame: (B_f, bins) descriptors at its basis voxels (B_f, 3); stored as float32 (values are weighted
    vote counts, float32 keeps 7 significant digits) and computed in float64."""
    with atomic_path(path) as tmp, _new(tmp, "descriptors") as f:
        _write_ragged(f, "descriptors", descriptors, np.float32)
        _write_ragged(f, "basis_ijk", basis_ijk, np.int32)
        _write_meta(f, meta)


def read_descriptors(path):
    """-> (list of (B_f, bins) float64 arrays, list of (B_f, 3) int arrays, meta)."""
    with _open(path, "descriptors") as f:
        _check_layout(f, path, "descriptors")
        desc = [d.astype(np.float64) for d in _read_ragged(f, "descriptors")]
        return desc, _read_ragged(f, "basis_ijk"), _read_meta(f)


# --- features/{exp}/{rig}/{desc}/{feat}/: the fitted transformation and per-frame features (Section 5) -----


def write_arrays(path, layout: str, arrays: dict, meta: dict) -> None:
    """A flat file of named arrays plus metadata (fitted models: MPPCA, K-means, pose PCA, MVRVM)."""
    with atomic_path(path) as tmp, _new(tmp, layout) as f:
        for key, value in arrays.items():
            f.create_dataset(key, data=np.asarray(value))
        _write_meta(f, meta)


def read_arrays(path, layout: str):
    """-> (dict of arrays, meta) of a file written by ``write_arrays`` with the same layout name."""
    with _open(path, layout) as f:
        _check_layout(f, path, layout)
        return {key: f[key][()] for key in f}, _read_meta(f)


def write_groups(path, layout: str, groups: dict, meta: dict, attrs: dict | None = None) -> None:
    """Named groups of arrays, each with its own metadata: ``groups[name] = (arrays, meta)`` (bundled models).

    ``attrs`` are extra scalar file attributes (e.g. a format version a reader checks before anything else).
    """
    with atomic_path(path) as tmp, _new(tmp, layout) as f:
        for key, value in (attrs or {}).items():
            f.attrs[key] = value
        for name, (arrays, group_meta) in groups.items():
            group = f.create_group(name)
            for key, value in arrays.items():
                value = np.asarray(value)
                group.create_dataset(key, data=value, compression="gzip" if value.size > 4096 else None)
            _write_meta(group, group_meta)
        _write_meta(f, meta)


def read_groups(path, layout: str, check=None):
    """-> ({name: (arrays, meta)}, meta) of a file written by ``write_groups``.

    ``check(attrs)`` runs on the file attributes before anything else is read. A missing piece (a
    damaged or hand-edited file) is a one-line error naming the file.
    """
    with _open(path, layout) as f:
        _check_layout(f, path, layout)
        if check is not None:
            check(f.attrs)
        try:
            groups = {name: ({k: g[k][()] for k in g}, _read_meta(g)) for name, g in f.items()}
            return groups, _read_meta(f)
        except (KeyError, OSError, ValueError) as err:
            raise VoxposeError(f"{path}: damaged {layout} file ({err})") from None


def write_per_motion(path, layout: str, motions: dict, meta: dict) -> None:
    """Named arrays per motion: ``motions[name][key]`` -> dataset ``/motions/name/key``."""
    with atomic_path(path) as tmp, _new(tmp, layout) as f:
        for name, arrays in motions.items():
            group = f.create_group(f"motions/{name}")
            for key, value in arrays.items():
                group.create_dataset(key, data=np.asarray(value), compression="gzip")
        _write_meta(f, meta)


def read_per_motion(path, layout: str):
    """-> ({motion: {key: array}}, meta) of a file written by ``write_per_motion``."""
    with _open(path, layout) as f:
        _check_layout(f, path, layout)
        motions = {name: {k: g[k][()] for k in g} for name, g in f["motions"].items()}
        return motions, _read_meta(f)


# --- voxels/{rig}/{motion}.h5: carved voxels, surface and basis voxels per frame (Sections 4, 6) ------------

_VOXEL_ARRAYS = ("ijk", "offsets", "surface", "basis", "basis_offsets", "empty", "shifts")


def voxel_arrays(seq) -> tuple[dict, dict]:
    """A ``voxelize.VoxelSequence`` as (arrays, meta), the form every file holding voxels stores."""
    arrays = {key: np.asarray(getattr(seq, key)) for key in _VOXEL_ARRAYS}
    return arrays, {"l_res": seq.l_res, "h_sub": seq.h_sub, "h_sub_frame": seq.h_sub_frame}


def voxels_from_arrays(arrays: dict, meta: dict):
    """Inverse of ``voxel_arrays``."""
    from .voxelize import VoxelSequence

    kept = {key: arrays[key] for key in _VOXEL_ARRAYS}
    return VoxelSequence(l_res=meta["l_res"], h_sub=meta["h_sub"], h_sub_frame=meta["h_sub_frame"], **kept)


def write_voxels(path, seq, meta: dict, angles=None) -> None:
    """A ``voxelize.VoxelSequence`` (sparse voxel coordinates, chunked and compressed), the rig's calibration
    and parameters in ``meta``, and the frames' ground-truth poses (F, 42) when known."""
    arrays, seq_meta = voxel_arrays(seq)
    with atomic_path(path) as tmp, _new(tmp, "voxels") as f:
        for key, value in arrays.items():
            f.create_dataset(key, data=value, compression="gzip" if value.size else None)
        if angles is not None:
            f.create_dataset("angles", data=angles)
        _write_meta(f, meta | seq_meta)


def read_voxels(path):
    """-> (VoxelSequence, meta, angles or None)."""
    with _open(path, "voxels") as f:
        _check_layout(f, path, "voxels")
        meta = _read_meta(f)
        arrays = {key: f[key][()] for key in _VOXEL_ARRAYS}
        angles = f["angles"][()] if "angles" in f else None
    return voxels_from_arrays(arrays, meta), meta, angles
