"""Input checks shared by every stage, and the squared distances several stages compute: one copy each.

Every check raises a one-line ``VoxposeError`` naming the input at fault (the caller's ``name``), or the
estimator used before ``fit``.
"""

import math
import numbers

import numpy as np

from voxpose.errors import NotFittedError, VoxposeError

_CHECK_ROWS = 4096  # rows checked for NaN at once: large descriptor sets are never copied whole
_DISTANCE_BLOCK = 1 << 18  # entries of |a|^2 + |b|^2 formed at once by squared_distances (2 MB)


def as_rows(a, name: str, n_cols: int | None = None, *, dtype=np.float64) -> np.ndarray:
    """``a`` as a non-empty 2-D array (rows, columns) of finite real numbers, else a ``VoxposeError``.

    ``n_cols``: the required number of columns (e.g. a fitted model's dimension). ``dtype``: the result's
    dtype (converted only when needed); ``None`` keeps the input's real dtype and never copies, for large
    float32 or integer descriptor sets. A NaN or infinite entry is reported with its row.
    """
    arr = np.asarray(a)
    if arr.ndim != 2:
        raise VoxposeError(f"{name}: expected a 2-D array (rows, columns), got shape {arr.shape}")
    if not (np.issubdtype(arr.dtype, np.floating) or np.issubdtype(arr.dtype, np.integer)):
        raise VoxposeError(f"{name}: expected real numbers, got dtype {arr.dtype}")
    if arr.shape[0] < 1 or arr.shape[1] < 1:
        raise VoxposeError(f"{name}: expected at least one row and one column, got shape {arr.shape}")
    if n_cols is not None and arr.shape[1] != n_cols:
        raise VoxposeError(f"{name}: expected {n_cols} columns, got {arr.shape[1]}")
    if np.issubdtype(arr.dtype, np.floating):
        for start in range(0, arr.shape[0], _CHECK_ROWS):
            bad = ~np.isfinite(arr[start : start + _CHECK_ROWS]).all(axis=1)
            if bad.any():
                raise VoxposeError(f"{name}: row {start + int(np.argmax(bad))} contains NaN or infinite values")
    return arr if dtype is None else arr.astype(dtype, copy=False)


def positive_number(value, name: str) -> float:
    """``value`` as a float when it is a finite real number > 0 (a bool or a string is none), else a
    ``VoxposeError`` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not 0 < value < math.inf:
        raise VoxposeError(f"{name} must be positive and finite, got {value!r}")
    return float(value)


def integer(value, name: str, minimum: int = 1) -> int:
    """``value`` as an int >= ``minimum`` (a bool is no integer here), else a ``VoxposeError`` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise VoxposeError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def squared_distances(a, b, a_norms=None) -> np.ndarray:
    """Squared Euclidean distances (n, m), float64, between the rows of ``a`` (n, d) and ``b`` (m, d).

    ``|a|^2 + |b|^2 - 2 a.b`` (one matrix product), with the round-off negatives clipped at zero. ``a_norms``:
    ``row_norms(a)`` when the caller has it already (the same numbers, without an (n, d) temporary per call).

    Computed in the product's own array: ``-2 a.b`` in place, then ``|a|^2 + |b|^2`` added to it block by block
    of rows. ``s + (-2 p)`` is ``s - 2 p`` bit for bit, so the numbers are those of the one-line formula, without
    its two (n, m) temporaries: for a kernel ridge fit on 10^4 rows these were 0.85 GB each, and allocating
    them (page faults) took 4.1 of the 5.7 s of its kernel matrix (10,297 x 200 rows, one thread; with the
    straight Cholesky copy of ``cholesky_solve``, ``benchmarks/bench_kernel_ridge.py`` went from 11.7 to 7.6 s).
    """
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    a_norms = row_norms(a) if a_norms is None else a_norms
    b_norms = row_norms(b)
    d2 = a @ b.T
    d2 *= -2.0
    step = max(1, _DISTANCE_BLOCK // max(1, d2.shape[1]))
    for start in range(0, d2.shape[0], step):
        d2[start : start + step] += a_norms[start : start + step, None] + b_norms[None, :]
    return np.maximum(d2, 0.0, out=d2)


def row_norms(a: np.ndarray) -> np.ndarray:
    """Squared Euclidean norm of every row of ``a`` (n, d) -> (n,), as ``squared_distances`` sums them."""
    return np.sum(a * a, axis=1)


def check_fitted(estimator, attribute: str) -> None:
    """A ``NotFittedError`` naming the estimator's class unless ``fit`` (or ``from_arrays``) set ``attribute``."""
    if not hasattr(estimator, attribute):
        raise NotFittedError(f"{type(estimator).__name__} is not fitted: call fit first")
