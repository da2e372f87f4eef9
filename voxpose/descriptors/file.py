"""Descriptor files of one motion: its 3D shape contexts per frame and their basis voxels (Section 4), and the 2D
shape contexts of its silhouette contours per image (the Agarwal & Triggs-style comparison)."""

import numpy as np

from voxpose.io.atomic import atomic_path
from voxpose.io.hdf5 import (
    check_layout,
    new_file,
    open_file,
    open_layout,
    read_arrays,
    read_meta,
    read_ragged,
    write_arrays,
    write_meta,
    write_ragged,
)

# --- descriptors/{rig}/{desc}/{motion}.h5: 3D shape contexts per frame (Section 4) -----------------------


def write_descriptors(path, descriptors: list, basis_ijk: list, meta: dict, reference_heading=None) -> None:
    """Per frame: (B_f, bins) descriptors at its basis voxels (B_f, 3); stored as float32 (values are weighted
    vote counts, float32 keeps 7 significant digits) and computed in float64. ``reference_heading`` (F,)
    degrees: the body frame's ``h0`` of every frame (``descriptors.body_frame``); None in the world frame."""
    with atomic_path(path) as tmp, new_file(tmp, "descriptors") as f:
        write_ragged(f, "descriptors", descriptors, np.float32)
        write_ragged(f, "basis_ijk", basis_ijk, np.int32)
        if reference_heading is not None:
            f.create_dataset("reference_heading", data=np.asarray(reference_heading, dtype=np.float64))
        write_meta(f, meta)


def read_descriptors(path):
    """-> (list of (B_f, bins) float64 arrays, list of (B_f, 3) int arrays, meta)."""
    with open_layout(path, "descriptors") as f:
        desc = [d.astype(np.float64) for d in read_ragged(f, "descriptors")]
        return desc, read_ragged(f, "basis_ijk"), read_meta(f)


def read_reference_heading(path) -> np.ndarray | None:
    """(F,) the body frame's reference heading of every frame in degrees; None for world-frame descriptors."""
    with open_layout(path, "descriptors") as f:
        return f["reference_heading"][()] if "reference_heading" in f else None


def write_contours(path, contexts, offsets, meta: dict) -> None:
    """2D shape contexts of every image, concatenated: image i's rows are ``contexts[offsets[i]:offsets[i + 1]]``."""
    write_arrays(path, "silhouette-contexts", {"contexts": contexts, "offsets": offsets}, meta)


def read_contours(path):
    """-> (contexts (N, bins), offsets (images + 1,), meta) of a file written by ``write_contours``."""
    arrays, meta = read_arrays(path, "silhouette-contexts")
    return arrays["contexts"], arrays["offsets"], meta


def contour_layout(path):
    """-> (offsets (images + 1,), meta) of a file written by ``write_contours``, without reading its contexts
    or checking its checksum (``read_contours`` does both when the contexts are needed)."""
    with open_file(path, "silhouette-contexts") as f:
        check_layout(f, path, "silhouette-contexts")
        return f["offsets"][()], read_meta(f)
