"""Input checks shared by every stage: one copy each, raising a one-line ``VoxposeError`` naming the input."""

import numpy as np

from voxpose.errors import VoxposeError


def as_rows(a, name: str, n_cols: int | None = None) -> np.ndarray:
    """``a`` as a finite float64 (n, d) array with n >= 1, else a ``VoxposeError`` naming ``name``."""
    arr = np.asarray(a, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[0] < 1 or arr.shape[1] < 1:
        raise VoxposeError(f"{name}: expected a non-empty 2-D array (rows, columns), got shape {arr.shape}")
    if n_cols is not None and arr.shape[1] != n_cols:
        raise VoxposeError(f"{name}: expected {n_cols} columns, got {arr.shape[1]}")
    if not np.all(np.isfinite(arr)):
        raise VoxposeError(f"{name}: holds NaN or infinite values")
    return arr
