"""Descriptor files of one motion: its 3D shape contexts per frame and their basis voxels (Section 4), and the 2D
shape contexts of its silhouette contours per image (the Agarwal & Triggs-style comparison)."""

from typing import NamedTuple

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


class DescriptorFile(NamedTuple):
    """A descriptor file's content: per frame (B_f, bins) float64 descriptors and (B_f, 3) basis voxels, the
    metadata, and the body frame's (F,) reference heading in degrees (None in the world frame)."""

    frames: list
    basis_ijk: list
    meta: dict
    reference_heading: np.ndarray | None


def read_descriptor_file(path, dtype=np.float64) -> DescriptorFile:
    """Everything in a descriptor file, read (and its checksum checked) once; the descriptors in ``dtype``, or as
    stored (float32) with None, for a reader that keeps a few of them (``features.training_set``)."""
    with open_layout(path, "descriptors") as f:
        desc = read_ragged(f, "descriptors")
        if dtype is not None:
            desc = [d.astype(dtype) for d in desc]
        heading = f["reference_heading"] if "reference_heading" in f else None
        return DescriptorFile(desc, read_ragged(f, "basis_ijk"), read_meta(f), heading)


def read_descriptors(path):
    """-> (list of (B_f, bins) float64 arrays, list of (B_f, 3) int arrays, meta)."""
    return tuple(read_descriptor_file(path)[:3])


def descriptor_headings(path) -> tuple[np.ndarray | None, dict]:
    """-> (the reference heading of every frame or None, meta) of a descriptor file, without reading its
    descriptors or checking its checksum (``read_descriptor_file`` does both when the descriptors are needed)."""
    with open_file(path, "descriptors") as f:
        check_layout(f, path, "descriptors")
        return (f["reference_heading"][()] if "reference_heading" in f else None), read_meta(f)


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
