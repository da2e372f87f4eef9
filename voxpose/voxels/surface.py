"""Surface voxels and basis voxels (Section 4, Figure 2).

Surface voxels are "voxels with at least one empty 6-neighborhood" (Section 4): about 2000 of a frame's
4000 occupied voxels. The 3D shape contexts are computed only at basis voxels, "about 200 obtained by
down-sampling surface voxels" (Figure 2). The paper does not say how it down-samples; we use grid
down-sampling, which matches "about 200" (the count follows the shape) and is cheap: the surface voxels
are binned into cubic cells of side ``s`` voxels, on a grid shifted by a seeded random offset, and each
non-empty cell contributes the voxel nearest its members' centroid. Every surface voxel then lies within
``s * sqrt(3)`` voxels of a basis voxel, and the basis is spread evenly over the surface. ``s`` is chosen
per frame so that the count lands near ``n_basis``: surfaces are two-dimensional, so the count varies
like ``s^-2``; from ``s = sqrt(1.35 N / n_basis)`` for N surface voxels (the factor 1.35 was measured on
carved bodies, where this first guess lands within about 10 % of ``n_basis``), secant steps
``s <- s sqrt(count / n_basis)`` keep the best ``s`` until the count is within 2 % (at most 8 steps).
The same seed gives the same basis. The compiled kernels (``surface_kernels``, selected by ``voxpose.kernels``)
count and pick the same cells in loops.
"""

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.kernels import use_numba
from voxpose.voxels import surface_kernels

_STEPS = 8
_TOLERANCE = 0.02  # stop when the count is within this fraction of n_basis
_FIRST_GUESS = 1.35  # cells of side sqrt(1.35 N / n) hold about n basis voxels on carved bodies


def _check_ijk(ijk, what: str) -> np.ndarray:
    ijk = np.asarray(ijk)
    if ijk.ndim != 2 or ijk.shape[1] != 3 or not np.issubdtype(ijk.dtype, np.integer):
        raise VoxposeError(f"{what}: expected integer voxel indices of shape (N, 3), got {ijk.dtype} {ijk.shape}")
    return ijk.astype(np.int64, copy=False)


def _box_index(columns, pad: int):
    """(flat index of every voxel in its bounding box widened by ``pad`` on each side, the box's strides, its
    size); ``columns`` are the three coordinate arrays, taken one by one because reductions along the short
    axis of an (N, 3) array are several times slower in numpy (28 against 6 us for 2000 voxels)."""
    local = [c - c.min() + pad for c in columns]
    sizes = [int(c.max()) + 1 + pad for c in local]
    strides = (sizes[1] * sizes[2], sizes[2], 1)
    return (local[0] * sizes[1] + local[1]) * sizes[2] + local[2], strides, sizes[0] * strides[0]


def surface_mask(ijk) -> np.ndarray:
    """(N,) bool: which of the occupied voxels ``ijk`` (N, 3) have an empty 6-neighbour."""
    ijk = _check_ijk(ijk, "surface_mask")
    if len(ijk) == 0:
        return np.zeros(0, dtype=bool)
    index, strides, size = _box_index(ijk.T, pad=1)  # the padding keeps every neighbour inside the box
    grid = np.zeros(size, dtype=bool)
    grid[index] = True
    full = np.ones(len(ijk), dtype=bool)
    for stride in strides:
        full &= grid.take(index + stride) & grid.take(index - stride)
    return ~full


def grid_sample(ijk, cell: float, offset=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Indices (sorted) of one voxel per non-empty grid cell: the one nearest its cell's centroid.

    Cells are cubes of side ``cell`` voxels; voxel ``x`` falls in cell ``floor((x + offset) / cell)``.
    Ties go to the lower index.
    """
    ijk = _check_ijk(ijk, "grid_sample")
    if not cell > 0:
        raise VoxposeError(f"grid_sample: cell must be positive, got {cell}")
    if len(ijk) == 0:
        return np.zeros(0, dtype=np.int64)
    keys, inverse = _cells(ijk, cell, offset)
    n_cells = len(keys)
    counts = np.bincount(inverse, minlength=n_cells)
    dist = 0.0
    for column in ijk.T:  # squared distance to the cell's centroid, summed over the axes in order
        centroid = np.bincount(inverse, column, minlength=n_cells) / counts
        dist = dist + (column - centroid.take(inverse)) ** 2
    order = np.lexsort((dist, inverse))  # stable: ties keep the lower index
    grouped = inverse.take(order)
    first = np.r_[True, grouped[1:] != grouped[:-1]]
    return np.sort(order[first])


def _cell_keys(ijk, cell, offset):
    """Each voxel's cell as one integer in ``0 .. n_keys - 1``, and ``n_keys``."""
    cells = [np.floor((ijk[:, a] + float(offset[a])) / cell).astype(np.int64) for a in range(3)]
    keys, _, n_keys = _box_index(cells, pad=0)
    return keys, n_keys


def _cells(ijk, cell, offset):
    """Unique cell keys (sorted) and each voxel's cell number, as ``np.unique(..., return_inverse=True)``."""
    key, n_keys = _cell_keys(ijk, cell, offset)
    present = np.bincount(key, minlength=n_keys) > 0
    return np.flatnonzero(present), (np.cumsum(present) - 1).take(key)


def _count_cells(ijk, cell, offset) -> int:
    """Number of non-empty cells."""
    key, n_keys = _cell_keys(ijk, cell, offset)
    return int(np.count_nonzero(np.bincount(key, minlength=n_keys)))


def basis_indices(surface_ijk, n_basis: int = 200, seed: int = 0) -> np.ndarray:
    """Indices (sorted) of about ``n_basis`` basis voxels among ``surface_ijk`` (N, 3) (Figure 2).

    Grid down-sampling with a cell size chosen per frame (module docstring); the grid's offset is drawn
    from ``numpy.random.default_rng(seed)``. With ``N <= n_basis`` every voxel is a basis voxel.
    """
    ijk = _check_ijk(surface_ijk, "basis_indices")
    if isinstance(n_basis, bool) or not isinstance(n_basis, int | np.integer) or n_basis < 1:
        raise VoxposeError(f"basis_indices: n_basis must be a positive integer, got {n_basis!r}")
    n = len(ijk)
    if n <= n_basis:
        return np.arange(n, dtype=np.int64)
    fraction = np.random.default_rng(seed).random(3)
    count_cells, sample = _count_cells, grid_sample
    if use_numba():
        count_cells, sample = surface_kernels.count_cells, surface_kernels.grid_sample
    cell = np.sqrt(_FIRST_GUESS * n / n_basis)
    best_cell, best_miss = cell, np.inf
    for _ in range(_STEPS):
        count = count_cells(ijk, cell, fraction * cell)
        miss = abs(count - n_basis)
        if miss < best_miss:
            best_cell, best_miss = cell, miss
        if miss <= _TOLERANCE * n_basis:
            break
        cell *= np.sqrt(count / n_basis)
    return sample(ijk, best_cell, fraction * best_cell)
