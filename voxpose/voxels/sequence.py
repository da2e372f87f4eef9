"""A voxel sequence (every frame's carved, surface and basis voxels) and its file layout (Sections 4 and 6)."""

from dataclasses import dataclass

import numpy as np

from voxpose.io.atomic import atomic_path
from voxpose.io.hdf5 import new_file, open_layout, read_meta, write_meta


@dataclass
class VoxelSequence:
    """Carved voxels of every frame of one sequence, concatenated over frames.

    Attributes
    ----------
    l_res : voxel side in metres; voxel ``ijk`` has its centre at ``(ijk + 0.5) * l_res``.
    h_sub : the subject's height (metres) measured on frame ``h_sub_frame`` at 0.05 m.
    ijk : (sum N_f, 3) int32 occupied voxels; frame f's are ``ijk[offsets[f]:offsets[f + 1]]``.
    offsets : (F + 1,) int64.
    surface : (sum N_f,) bool, aligned with ``ijk``: voxels with an empty 6-neighbour.
    basis : (sum B_f,) int32 indices of the basis voxels into their frame's voxels;
        frame f's are ``basis[basis_offsets[f]:basis_offsets[f + 1]]``.
    basis_offsets : (F + 1,) int64.
    empty : (F,) bool, frames whose hull is empty.
    shifts : (F, 3) metres added to the body before rendering (``follow_subject``); zeros for real data.
    silhouettes : (F, C, H, W) bool when kept, else None.
    """

    l_res: float
    h_sub: float
    h_sub_frame: int
    ijk: np.ndarray
    offsets: np.ndarray
    surface: np.ndarray
    basis: np.ndarray
    basis_offsets: np.ndarray
    empty: np.ndarray
    shifts: np.ndarray
    silhouettes: np.ndarray | None = None

    @property
    def n_frames(self) -> int:
        return len(self.empty)

    def frame(self, f: int):
        """(ijk (N, 3), surface (N,), basis (B,)) of frame ``f``."""
        a, b = self.offsets[f], self.offsets[f + 1]
        return self.ijk[a:b], self.surface[a:b], self.basis[self.basis_offsets[f] : self.basis_offsets[f + 1]]

    def counts(self) -> dict:
        """Per-frame counts (F,) of ``occupied``, ``surface`` and ``basis`` voxels."""
        occupied = np.diff(self.offsets)
        frame_of_voxel = np.repeat(np.arange(self.n_frames), occupied)
        surface = np.bincount(frame_of_voxel, weights=self.surface, minlength=self.n_frames).astype(np.int64)
        return {"occupied": occupied, "surface": surface, "basis": np.diff(self.basis_offsets)}


# --- voxels/{rig}/{motion}.h5: carved voxels, surface and basis voxels per frame (Sections 4, 6) ------------

_VOXEL_ARRAYS = ("ijk", "offsets", "surface", "basis", "basis_offsets", "empty", "shifts")


def voxel_arrays(seq) -> tuple[dict, dict]:
    """A ``voxels.sequence.VoxelSequence`` as (arrays, meta), the form every file holding voxels stores."""
    arrays = {key: np.asarray(getattr(seq, key)) for key in _VOXEL_ARRAYS}
    return arrays, {"l_res": seq.l_res, "h_sub": seq.h_sub, "h_sub_frame": seq.h_sub_frame}


def voxels_from_arrays(arrays: dict, meta: dict):
    """Inverse of ``voxel_arrays``."""
    kept = {key: arrays[key] for key in _VOXEL_ARRAYS}
    return VoxelSequence(l_res=meta["l_res"], h_sub=meta["h_sub"], h_sub_frame=meta["h_sub_frame"], **kept)


def write_voxels(path, seq, meta: dict, angles=None) -> None:
    """A ``voxels.sequence.VoxelSequence`` (sparse voxel coordinates, chunked and compressed), the rig's calibration
    and parameters in ``meta``, and the frames' ground-truth poses (F, 42) when known."""
    arrays, seq_meta = voxel_arrays(seq)
    with atomic_path(path) as tmp, new_file(tmp, "voxels") as f:
        for key, value in arrays.items():
            f.create_dataset(key, data=value, compression="gzip" if value.size else None)
        if angles is not None:
            f.create_dataset("angles", data=angles)
        write_meta(f, meta | seq_meta)


def read_voxels(path):
    """-> (VoxelSequence, meta, angles or None)."""
    with open_layout(path, "voxels") as f:
        meta = read_meta(f)
        arrays = {key: f[key][()] for key in _VOXEL_ARRAYS}
        angles = f["angles"][()] if "angles" in f else None
    return voxels_from_arrays(arrays, meta), meta, angles
