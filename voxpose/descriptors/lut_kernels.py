"""Compiled (numba) kernel of the 3D shape context fast path with soft votes: one loop over the pairs.

The numpy path (:mod:`voxpose.descriptors.lut`) looks every (basis, surface) pair up in a table of 33,344
offsets x 8 slot weights (2.1 MB at the paper's settings). In a compiled loop the arithmetic is cheap and
those random reads from beyond the core's cache are most of the cost, so the kernel keeps a table an eighth
of that size: soft votes are symmetric under the reflections of the offset along x, y and z, so only offsets
with ``x, y, z >= 0`` are tabulated, and the votes of ``(+-x, +-y, +-z)`` are those of ``(|x|, |y|, |z|)``
with their bins reflected:

- ``z -> -z`` turns azimuth ``phi`` into ``-phi``: azimuth sector ``k`` becomes ``n_a - 1 - k``;
- ``x -> -x`` turns ``phi`` into ``180 - phi``: sector ``k`` becomes ``n_a / 2 - 1 - k`` (mod ``n_a``), for an even
  ``n_a`` only (an odd one keeps both signs of x in the table);
- ``y -> -y`` turns elevation ``theta`` into ``180 - theta``: elevation sector ``k`` becomes ``n_e - 1 - k``.

Soft votes interpolate linearly between bin centres, which these maps carry onto bin centres, and split a
vote on a boundary equally, so a reflected offset's votes are the same weights in the reflected bins (hard
votes are not symmetric on boundaries, which belong to one side: they stay on the numpy path, where the loop
did not beat ``np.bincount``). The table's votes come from the reference's own
:func:`voxpose.descriptors.shape_context.offset_votes`, and every offset of the support is checked against
its reflected votes when the table is built (equal to 1e-14; the votes are computed by floating-point
trigonometry, so a reflection may move one by a unit in the last place). A pair's votes are added in surface
order, so descriptors equal the reference up to the order of additions
(``tests/descriptors/test_lut_kernels.py``). Selected by :mod:`voxpose.kernels`.

The loop visits only surface voxels that can be in a basis voxel's support: the surface voxels (sorted by x,
then y, then z) are indexed by column (x, y), so that for each x within the radius the voxels whose y lies
within the support's reach at that x form one run, and the support's reach in z at (x, y) skips the rest
before the table is read. Most of the loop's time went to voxels outside the support (1675 visited per basis
voxel for 962 in it on ``benchmarks/bench_shape_context.py``'s figures); the votes and their order are
unchanged, so the descriptors are the same bit for bit.
"""

import functools
import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from voxpose.descriptors.shape_context import BinGeometry, offset_votes
from voxpose.kernels import jit

_CHECK = 1e-14
"""Largest difference allowed between an offset's votes and its reflected table row's (module docstring)."""


@dataclass(frozen=True, eq=False)
class FoldedTable:
    """Soft votes of the offsets folded onto ``x, y, z >= 0`` (module docstring).

    ``cube[(cx * size[1] + cy) * size[2] + cz]`` is the row of folded offset ``c`` (its absolute value on a
    folded axis, ``offset + radius`` on the x axis when it is not folded), -1 outside the support. Row ``o``
    votes ``weights[o, :]`` into bins ``bins[o, :]`` and, when it has more than ``WIDTH`` votes (the
    vertical axis), ``extra_weights[extra_start[o]:extra_start[o + 1]]`` into ``extra_bins[...]``. Rows
    with fewer votes are padded with votes of weight 0 into bins ``n_bins + slot`` (a fixed count of votes
    per row: a loop of varying length mispredicts its end at most pairs, measured 1.4x slower).
    ``flip[signs, bin]`` reflects a bin by the signs of a pair's offset (bit 1 for x < 0, 2 for y < 0, 4 for
    z < 0) and keeps the padding bins; ``signed_bins[signs, o]`` are row ``o``'s bins so reflected (8 x the
    bins' 37 KB at the paper's settings; measured 8 % faster than reflecting each vote). ``y_reach[cx]`` is the
    largest ``|y|`` of the support at ``cx`` and ``z_reach[cx, |y|]`` the largest ``|z|`` (-1 for none): the kernel
    visits only surface voxels within them.
    """

    radius: int
    fold_x: bool
    size: tuple
    cube: np.ndarray  # int32
    bins: np.ndarray  # (R, WIDTH) uint8 or int32
    weights: np.ndarray  # (R, WIDTH) float64
    extra_start: np.ndarray  # (R + 1,) int64
    extra_bins: np.ndarray
    extra_weights: np.ndarray
    flip: np.ndarray  # (8, n_bins + WIDTH)
    signed_bins: np.ndarray  # (8, R, WIDTH): flip[signs][bins], so that the loop reads a pair's bins directly
    y_reach: np.ndarray  # (size[0],) int64
    z_reach: np.ndarray  # (size[0], radius + 1) int64


WIDTH = 8
"""Votes per table row (the others: padding, or the few longer rows' extra votes)."""


def _csr_votes(offsets: np.ndarray, geometry: BinGeometry) -> sp.csr_array:
    """The reference's soft votes of integer ``offsets`` (P, 3): (P, n_bins), each row's bins sorted."""
    owner, bins, weights = offset_votes(offsets, geometry, soft=True)
    votes = sp.csr_array((weights, (owner, bins)), shape=(len(offsets), geometry.n_bins))
    votes.sum_duplicates()
    return votes


def _flips(geometry: BinGeometry) -> np.ndarray:
    """(8, n_bins + WIDTH) bin maps of the reflections, row ``x_bit + 2 y_bit + 4 z_bit``; padding bins stay."""
    n_e, n_a = geometry.n_e, geometry.n_a
    i_r, i_e, i_a = np.unravel_index(np.arange(geometry.n_bins), (geometry.n_r, n_e, n_a))
    flips = np.empty((8, geometry.n_bins + WIDTH), dtype=np.int64)
    flips[:, geometry.n_bins :] = geometry.n_bins + np.arange(WIDTH)
    for signs in range(8):
        e = n_e - 1 - i_e if signs & 2 else i_e
        a = (n_a // 2 - 1 - i_a) % n_a if signs & 1 else i_a
        a = n_a - 1 - a if signs & 4 else a
        flips[signs, : geometry.n_bins] = geometry.bin_index(i_r, e, a)
    return flips


@functools.lru_cache(maxsize=16)
def folded_table(geometry: BinGeometry) -> FoldedTable:
    """The folded soft-vote table of one geometry (cached), checked against every offset of the support."""
    radius = math.floor(geometry.r_max)
    fold_x = geometry.n_a % 2 == 0
    x_axis = np.arange(0 if fold_x else -radius, radius + 1)
    half = np.arange(radius + 1)
    grid = np.stack(np.meshgrid(x_axis, half, half, indexing="ij"), axis=-1).reshape(-1, 3)
    votes = _csr_votes(grid, geometry)
    support = np.flatnonzero(np.diff(votes.indptr))
    if len(support) == 0:
        raise geometry.empty_support_error()
    cube = np.full(len(grid), -1, dtype=np.int32)
    cube[support] = np.arange(len(support), dtype=np.int32)
    votes = votes[support]
    dtype = np.uint8 if geometry.n_bins + WIDTH <= 256 else np.int32
    count = np.diff(votes.indptr)
    row = np.repeat(np.arange(len(support)), count)
    slot = np.arange(votes.nnz) - np.repeat(votes.indptr[:-1], count)
    head = slot < WIDTH
    bins = np.tile(geometry.n_bins + np.arange(WIDTH), (len(support), 1))
    weights = np.zeros((len(support), WIDTH))
    bins[row[head], slot[head]] = votes.indices[head]
    weights[row[head], slot[head]] = votes.data[head]
    extra_start = np.concatenate([[0], np.cumsum(np.maximum(count - WIDTH, 0))])
    flips = _flips(geometry).astype(dtype)
    table = FoldedTable(radius=radius, fold_x=fold_x, size=(len(x_axis), radius + 1, radius + 1), cube=cube,
                        bins=bins.astype(dtype), weights=weights, extra_start=extra_start,
                        extra_bins=votes.indices[~head].astype(dtype), extra_weights=votes.data[~head],
                        flip=flips, signed_bins=np.ascontiguousarray(flips[:, bins]).astype(dtype),
                        **_reach(cube, (len(x_axis), radius + 1, radius + 1)))  # fmt: skip
    _check(table, geometry)
    return table


def _reach(cube: np.ndarray, size: tuple) -> dict:
    """``y_reach`` and ``z_reach`` of a folded table's ``cube`` of ``size`` (``FoldedTable``)."""
    inside = cube.reshape(size) >= 0
    z_reach = np.where(inside.any(axis=2), size[2] - 1 - np.argmax(inside[:, :, ::-1], axis=2), -1)
    y_reach = np.where(z_reach.max(axis=1) >= 0, size[1] - 1 - np.argmax(z_reach[:, ::-1] >= 0, axis=1), -1)
    return {"y_reach": y_reach.astype(np.int64), "z_reach": z_reach.astype(np.int64)}


def _check(table: FoldedTable, geometry: BinGeometry) -> None:
    """Every offset of the cube ``-radius .. radius`` votes as its folded row, reflected (module docstring)."""
    r = table.radius
    axis = np.arange(-r, r + 1)
    cube = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    direct = _csr_votes(cube, geometry)
    rows = table.cube[_folded_index(cube, table)]
    signs = (cube[:, 0] < 0) * int(table.fold_x) + (cube[:, 1] < 0) * 2 + (cube[:, 2] < 0) * 4
    owner = np.flatnonzero(rows >= 0)
    bins = table.flip[signs[owner, None], table.bins[rows[owner]]]
    n_extra = np.diff(table.extra_start)[rows[owner]]
    extra = np.arange(n_extra.sum()) + np.repeat(table.extra_start[rows[owner]] - np.cumsum(n_extra) + n_extra,
                                                 n_extra)  # fmt: skip
    extra_owner = np.repeat(owner, n_extra)
    owners = np.concatenate([np.repeat(owner, WIDTH), extra_owner])
    bins = np.concatenate([bins.ravel(), table.flip[signs[extra_owner], table.extra_bins[extra]]])
    weights = np.concatenate([table.weights[rows[owner]].ravel(), table.extra_weights[extra]])
    folded = sp.csr_array((weights, (owners, bins.astype(np.int64))), shape=(len(cube), table.flip.shape[1]))
    if abs(direct - folded[:, : geometry.n_bins]).max() > _CHECK or folded[:, geometry.n_bins :].count_nonzero():
        raise AssertionError("3DSC kernel: a reflected offset's soft votes differ from its own (module docstring)")


def _folded_index(offsets: np.ndarray, table: FoldedTable) -> np.ndarray:
    """Index into ``table.cube`` of integer offsets (P, 3) within the radius."""
    r = table.radius
    x = np.abs(offsets[:, 0]) if table.fold_x else offsets[:, 0] + r
    return (x * table.size[1] + np.abs(offsets[:, 1])) * table.size[2] + np.abs(offsets[:, 2])


def soft_votes(geometry: BinGeometry, surface: np.ndarray, basis: np.ndarray) -> np.ndarray:
    """Soft-vote descriptors (M, n_bins) at basis voxels (M, 3) over surface voxels (N, 3, in lexicographic
    order), both int64 and non-empty (``ShapeContextTable.describe`` refuses empty sets)."""
    t = folded_table(geometry)
    out = _soft_votes(surface, basis, t.radius, t.fold_x, t.size[1], t.size[2], t.cube, t.signed_bins, t.weights,
                      t.extra_start, t.extra_bins, t.extra_weights, t.flip, t.y_reach, t.z_reach)  # fmt: skip
    return out[:, : geometry.n_bins]


@jit
def _soft_votes(surface, basis, radius, fold_x, size_y, size_z, cube, signed_bins, weights, extra_start, extra_bins,
                extra_weights, flip, y_reach, z_reach):  # fmt: skip  # pragma: no cover (compiled)
    out = np.zeros((basis.shape[0], flip.shape[1]))
    n = surface.shape[0]
    x0, x1 = surface[0, 0], surface[n - 1, 0]
    y0, y1 = surface[0, 1], surface[0, 1]
    for s in range(n):
        y0 = min(y0, surface[s, 1])
        y1 = max(y1, surface[s, 1])
    ny = y1 - y0 + 1
    start = np.zeros((x1 - x0 + 1) * ny + 1, dtype=np.int64)  # surface voxels of column (x, y) from start[.]
    for s in range(n):
        start[(surface[s, 0] - x0) * ny + surface[s, 1] - y0 + 1] += 1
    for c in range(len(start) - 1):
        start[c + 1] += start[c]
    for b in range(basis.shape[0]):
        bi, bj, bk = basis[b, 0], basis[b, 1], basis[b, 2]
        for x in range(max(bi - radius, x0), min(bi + radius, x1) + 1):
            dx = x - bi
            xi = abs(dx) if fold_x else dx + radius
            low = max(bj - y_reach[xi], y0)
            high = min(bj + y_reach[xi], y1)
            if low > high:  # also where no offset of this dx is in the support (y_reach -1)
                continue
            column = (x - x0) * ny - y0
            for s in range(start[column + low], start[column + high + 1]):  # sorted by y, then z
                y = surface[s, 1] - bj
                z = surface[s, 2] - bk
                if abs(z) > z_reach[xi, abs(y)]:
                    continue
                row = cube[(xi * size_y + abs(y)) * size_z + abs(z)]
                if row < 0:
                    continue
                signs = 2 * (y < 0) + 4 * (z < 0) + (fold_x and dx < 0)
                for v in range(WIDTH):
                    out[b, signed_bins[signs, row, v]] += weights[row, v]
                for v in range(extra_start[row], extra_start[row + 1]):
                    out[b, flip[signs, extra_bins[v]]] += extra_weights[v]
    return out
