"""Lookup-table fast path for 3D shape contexts on voxel grids (Sun et al. 2006, Section 4, third bullet).

Voxels lie on a grid, so the weighted votes of every integer offset inside the support are computed once
per parameter set by :func:`voxpose.descriptors.shape_context.offset_votes` (the reference's own definition of a
vote, so both paths agree on every boundary) and kept in a table, one row per offset. A frame is then
described by "voxel - offset vector - bin" indexing, in two steps:

1. pairs: every (basis, surface) pair finds its offset's table row by one integer lookup. Voxels are
   packed into integer codes whose differences decode the offset uniquely, and a code table maps a
   code difference to a table row or to "outside the support". One code table serves every frame whose
   extent it covers and grows when a frame does not fit, so a motion needs one or a few;
2. accumulation: descriptor ``b`` is the sum of the table rows of its pairs.

Step 2 groups table rows by the set of bins they vote for, so that each group is one fixed map to bins:

- counting (hard votes): rows repeat exactly (at most one distinct row per bin, plus one per shell and
  pole for the vertical axis), so one ``np.bincount`` counts pairs per (basis, distinct row) and a
  small sparse product turns the counts into descriptors;
- segments (soft votes): rows are all distinct (about 5 partial votes each), but only a few hundred
  distinct sets of bins occur. A run is one basis voxel's pairs of one group: its summed per-offset weights
  (``width`` columns) go to the group's bins. Each basis voxel's pair rows are sorted in blocks of
  ``_BLOCK`` surface voxels, so that a block's pairs come by group, and the runs are numbered by (basis
  voxel, group); one sparse (COO) x dense product sums every run's weights, and one ``np.bincount`` sends
  the sums to the bins. Surface voxels are taken in lexicographic order and a group's table rows are in
  lexicographic order of their offsets, so a run's pairs arrive in ascending row order block after block,
  and the COO product (which adds its entries in storage order) sums each run exactly as if it had been
  sorted whole: the descriptors do not depend on the order of the surface voxels, bit for bit.

Measured (``benchmarks/bench_shape_context.py`` figures: ~1770 surface and 200 basis voxels, ~190,000
pairs in the support per frame; process CPU time per frame, medians, on the 2-core VM while other jobs
kept both cores busy, load average 3 - 6):

- soft votes, segments with whole-row sorts and a CSR product (the previous version): 9.4 - 10.6 ms per
  frame, of which pair codes and lookup 1.3, row sort 0.8, dropping pairs outside the support 0.7, runs
  1.1, CSR x dense product 2.3 to 2.6, run keys and bincount 1.7; hard votes, counting: 3.8 - 4.5 ms
  (previously 8 - 9 ms). The reference takes 23 - 34 times longer on the same frames;
- numpy sorts rows of at most 512 16-bit values several times faster per value than longer ones (0.25
  against 1.4 - 1.9 ms for the ~450,000 pairs of a predict benchmark frame, load average 12): sorting in
  blocks of 512 with the COO product took 6.2 ms per frame against 7.1 ms for whole rows and the CSR
  product, in the same process; blocks of 256: 6.3 ms; no sort at all (runs numbered straight from the
  lexicographic order): 6.4 ms;
- one code table per frame extent (the previous design) was rebuilt for most frames of moving figures,
  ~2 ms per frame; the grown table is built once or twice per motion;
- scipy converts sparse index arrays that are not int32 (uint16 rows, int64 run starts) slowly: 0.5 - 3
  ms per product, against 0.03 ms for int32 arrays, so they are passed as int32;
- alternatives for soft votes: summing the runs by ``np.add.reduceat`` over gathered table rows, 11 -
  13 ms (against 2.2 ms for the CSR product); keeping the pairs outside the support as a zero row
  instead of dropping them, 12 ms per frame; the sparse product ``A @ T`` of the (basis x offset) pair
  indicator with the table (scipy CSR x CSR, no sort needed), 9 ms for the product alone;
  ``np.bincount`` over the (basis, bin) keys of all partial votes, padded to 8 per pair: 23 ms; only
  pairing each basis voxel with the surface voxels within the table radius along the lead axis (a
  window of ~88% of them on human figures): no gain; grouping the pairs by scipy's counting-sort
  conversions (CSR to CSC and back) instead of sorting: no gain.

Soft votes run in a compiled loop (:mod:`voxpose.descriptors.lut_kernels`, numba) when :mod:`voxpose.kernels`
selects it: the same votes from a table folded by the reflections of the offsets, 1.5 - 1.9x faster than the
numpy path described above (process CPU time per frame, medians, ``benchmarks/bench_shape_context.py`` run
alternately with ``VOXPOSE_KERNELS=numpy`` and without: 7.00 and 5.65 against 3.69 and 3.53 ms at load average
11 - 12 on the 2 cores; 4.74 and 5.32 against 3.14 and 3.09 ms at load average 3.6; 2.96 ms at load 0.3). Hard
votes stay on the numpy path (``np.bincount`` was faster than the loop).

``ShapeContextTable.describe_frames(frames, threads=2)`` describes frames on a thread pool. The numpy
and scipy calls above release the GIL (a Python thread kept running during each of them), so two
threads can use two cores; with the VM's two cores busy with other jobs, no gain was measurable.

A dense 3D convolution of the occupancy grid with each bin's kernel needs about ``n_bins`` grid-sized
FFTs per frame, far slower, and was not pursued. Small dense products go through scipy's sparse kernels
rather than BLAS: multithreaded OpenBLAS took ~20 ms per call to wake its threads on the loaded machine.
"""

import contextlib
import functools
import logging
import math
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from voxpose.descriptors import lut_kernels
from voxpose.descriptors.settings import DescriptorSettings
from voxpose.descriptors.shape_context import BinGeometry, normalise_rows, offset_votes
from voxpose.errors import VoxposeError
from voxpose.kernels import use_numba

log = logging.getLogger(__name__)

_CHUNK_PAIRS = 1 << 19
"""Basis voxels are processed in chunks of about this many (basis, surface) pairs, to bound memory."""

_MAX_CODE_TABLE = 1 << 26
"""Largest per-frame code table (entries) allowed; a voxel set spanning more is refused."""

_WIDE_QUANTILE = 0.99

_BLOCK = 512
"""Soft votes: each basis voxel's pairs are sorted in blocks of this many surface voxels (module docstring)."""
"""Segment width: this quantile of the votes per row; longer rows (the vertical axis) get a bin each."""


@dataclass(frozen=True, eq=False)
class OffsetTable:
    """Votes of every integer offset in the support, for one geometry and voting mode.

    The votes of row ``o`` are ``weights[o, k]`` into extended bin ``group_bins[group[o], k]``. Extended
    bins ``n_bins .. n_ext - 1`` stand for whole rows too long for ``width`` slots (their votes are the
    columns of ``extra``), bin ``n_ext`` is a sink for empty slots. With ``counting``, all rows of a
    group are equal and ``group_votes`` (n_bins, n_groups) holds them instead of ``weights``.
    """

    radius: int  # every support offset has |component| <= radius
    offsets: np.ndarray  # (R, 3) int64 support offsets, one per row, rows sorted by group
    group: np.ndarray  # (R,) int32 group of each row
    counting: bool
    group_votes: sp.csr_array | None  # counting: (n_bins, n_groups) votes of each group
    weights: np.ndarray | None  # segments: (R, width) float64 slot weights of each row
    group_bins: np.ndarray | None  # segments: (n_groups, width) int64 extended bin of each slot
    extra: sp.csr_array | None  # segments: (n_bins, n_ext - n_bins) votes of the extended bins

    @property
    def n_groups(self) -> int:
        return int(self.group[-1]) + 1


def _slots(votes: sp.csr_array, width: int, sink: int):
    """Votes of rows of at most ``width`` votes as padded ``(R, width)`` bins (``sink``) and weights (0)."""
    nnz = np.diff(votes.indptr)
    row = np.repeat(np.arange(votes.shape[0]), nnz)
    slot = np.arange(votes.nnz) - np.repeat(votes.indptr[:-1], nnz)
    short = nnz[row] <= width
    bins = np.full((votes.shape[0], width), sink, dtype=np.int64)
    weights = np.zeros((votes.shape[0], width))
    bins[row[short], slot[short]] = votes.indices[short]
    weights[row[short], slot[short]] = votes.data[short]
    return bins, weights


def _distinct_rows(keys: np.ndarray):
    """Group equal rows of an integer ``(R, k)`` array: ``(first, inverse)`` as ``np.unique(axis=0)`` gives.

    ``np.lexsort`` on the columns is much faster here than ``np.unique(axis=0)``, which sorts void views.
    """
    order = np.lexsort(keys.T[::-1])
    ordered = keys[order]
    new = np.ones(len(keys), dtype=bool)
    new[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    inverse = np.empty(len(keys), dtype=np.int64)
    inverse[order] = np.cumsum(new) - 1
    return order[new], inverse


@functools.lru_cache(maxsize=16)
def offset_table(geometry: BinGeometry, soft: bool) -> OffsetTable:
    """The lookup table of one parameter set (cached): the votes of all integer offsets in the support."""
    n_bins = geometry.n_bins
    radius = math.floor(geometry.r_max)
    axis = np.arange(-radius, radius + 1)
    cube = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    owner, bins, weights = offset_votes(cube, geometry, soft=soft)
    votes = sp.csr_array((weights, (owner, bins)), shape=(len(cube), n_bins))
    votes.sum_duplicates()  # also sorts each row's bins
    support = np.flatnonzero(np.diff(votes.indptr))
    if len(support) == 0:
        raise geometry.empty_support_error()
    votes, offsets = votes[support], cube[support]
    nnz = np.diff(votes.indptr)

    slot_bins, slot_weights = _slots(votes, int(nnz.max()), n_bins)
    first, distinct = _distinct_rows(np.hstack([slot_bins, slot_weights.view(np.int64)]))
    counting = len(first) <= 4 * n_bins  # hard votes: at most n_bins + 2 n_r distinct rows; soft: ~all
    if counting:
        group, group_votes = distinct, sp.csr_array(votes[first].T)
        weights = group_bins = extra = None
    else:
        width = int(np.quantile(nnz, _WIDE_QUANTILE, method="higher"))
        wide = np.flatnonzero(nnz > width)
        slot_bins, weights = _slots(votes, width, n_bins + len(wide))
        slot_bins[wide, 0] = n_bins + np.arange(len(wide))
        weights[wide, 0] = 1.0
        extra = sp.csr_array(votes[wide].T)
        first, group = _distinct_rows(slot_bins)
        group_bins, group_votes = slot_bins[first], None
    order = np.argsort(group, kind="stable")  # within a group, offsets stay in lexicographic order (cube)
    group = group[order].astype(np.int32)  # int32: half the traffic of the per-pair group lookup
    log.info(
        "3DSC lookup table: R_max %.4g voxels, %d offsets, %d votes, %d groups (%s)",
        geometry.r_max,
        len(offsets),
        votes.nnz,
        group[-1] + 1,
        "counting" if counting else f"segments of width {weights.shape[1]}",
    )
    return OffsetTable(
        radius=radius,
        offsets=offsets[order],
        group=group,
        counting=counting,
        group_votes=group_votes,
        weights=None if weights is None else weights[order],
        group_bins=group_bins,
        extra=extra,
    )


def _column_min(ijk: np.ndarray) -> np.ndarray:
    """``ijk.min(axis=0)`` of (N, 3) voxels, column by column (several times faster in numpy)."""
    return np.array([ijk[:, a].min() for a in range(3)])


def _column_max(ijk: np.ndarray) -> np.ndarray:
    """``ijk.max(axis=0)`` of (N, 3) voxels, column by column."""
    return np.array([ijk[:, a].max() for a in range(3)])


def _codes(ijk: np.ndarray, low: np.ndarray, strides: np.ndarray) -> np.ndarray:
    """``(ijk - low) @ strides`` (integers, exact), column by column."""
    return (ijk[:, 0] - low[0]) * strides[0] + (ijk[:, 1] - low[1]) * strides[1] + (ijk[:, 2] - low[2]) * strides[2]


def _lexicographic_order(ijk: np.ndarray) -> np.ndarray:
    """Indices putting voxels ``ijk`` (N, 3) in lexicographic order (i, then j, then k; equal voxels in any)."""
    low = _column_min(ijk)
    span = _column_max(ijk) - low + 1
    return np.argsort(_codes(ijk, low, np.array([span[1] * span[2], span[2], 1])))


def _as_voxels(name: str, values) -> np.ndarray:
    arr = np.asarray(values)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise VoxposeError(f"shape context: {name} must have shape (N, 3), got {arr.shape}")
    if len(arr) == 0:
        raise VoxposeError(f"shape context: {name} is empty")
    if np.issubdtype(arr.dtype, np.floating):
        bad = ~np.isfinite(arr).all(axis=1)
        if bad.any():
            raise VoxposeError(f"shape context: {name} row {int(np.argmax(bad))} is not finite: {arr[bad][0]}")
    if not np.issubdtype(arr.dtype, np.integer):
        raise VoxposeError(f"shape context: {name} must hold integer voxel indices, got dtype {arr.dtype}")
    return arr.astype(np.int64, copy=False)


class ShapeContextTable:
    """3D shape contexts of voxel sets by table lookup; equal to :func:`shape_contexts` on voxel centres.

    Parameters are those of :func:`voxpose.descriptors.shape_context.shape_contexts`, with the subject height in
    voxels ``h_sub_voxels = h_sub / l_res`` (60 in the paper) in place of ``l_res`` and ``h_sub``: on the
    grid only their ratio matters. The offset table is cached per parameter set (module-wide), the code
    table per instance.
    """

    def __init__(self, h_sub_voxels, **params):
        settings = DescriptorSettings.from_config(params, "shape context")
        self.geometry = BinGeometry.from_settings(settings, h_sub_voxels)
        self.soft = bool(settings.soft)
        self.normalise = bool(settings.normalise)
        if self.soft and use_numba():  # the kernel's table, built (and checked) now: an empty support fails here
            lut_kernels.folded_table(self.geometry)
        else:
            self.table  # noqa: B018 (built now, for the same reason)
        self._codes = None  # the current _CodeTable, grown to the largest extent seen
        self._codes_lock = threading.Lock()

    @functools.cached_property
    def table(self) -> OffsetTable:
        """The numpy path's offset table (built only when used: 0.1 s of CPU per process)."""
        return offset_table(self.geometry, self.soft)

    @property
    def n_bins(self) -> int:
        return self.geometry.n_bins

    def _code_table(self, extent: np.ndarray) -> "_CodeTable":
        """The code table for a voxel set of ``extent`` (max - min per axis); grown when one is too small.

        One table serves every frame whose extent it covers, so a motion needs one or a few tables (a
        table per extent would be rebuilt for most frames of a moving figure). Thread safe.
        """
        codes = self._codes
        if codes is not None and codes.covers(extent):
            return codes
        with self._codes_lock:
            codes = self._codes
            if codes is None or not codes.covers(extent):
                grown = extent if codes is None else np.maximum(codes.seen, extent)
                try:
                    codes = _CodeTable.build(self.table, grown)
                except VoxposeError:
                    codes = _CodeTable.build(self.table, extent)  # this frame alone may still fit
                self._codes = codes
        return codes

    def describe(self, surface_ijk, basis_ijk) -> np.ndarray:
        """Descriptors ``(M, n_bins)`` float64 at the basis voxels, from the surface voxels.

        Parameters
        ----------
        surface_ijk : (N, 3) int array
            Surface voxel indices on a world-aligned grid, Y up.
        basis_ijk : (M, 3) int array
            Basis voxel indices: the descriptor centres.
        """
        surface = _as_voxels("surface_ijk", surface_ijk)
        basis = _as_voxels("basis_ijk", basis_ijk)
        if self.soft and use_numba():  # the compiled kernel (voxpose.kernels, descriptors.lut_kernels)
            out = lut_kernels.soft_votes(self.geometry, surface[_lexicographic_order(surface)], basis)
        else:
            out = self._finish(self._numpy_votes(surface, basis))
        return normalise_rows(out) if self.normalise else out

    def _numpy_votes(self, surface: np.ndarray, basis: np.ndarray) -> np.ndarray:
        """Votes of the basis voxels (``_finish`` gives the descriptors), by array operations (module docstring)."""
        t = self.table
        if not t.counting:  # so that each run meets its table rows in ascending order (module docstring)
            surface = surface[_lexicographic_order(surface)]
        low = np.minimum(_column_min(surface), _column_min(basis))
        high = np.maximum(_column_max(surface), _column_max(basis))
        codes = self._code_table(high - low)
        surface_code = _codes(surface, low, codes.strides) + codes.shift
        basis_code = _codes(basis, low, codes.strides)
        if not t.counting:  # whole blocks: padded with a code beyond every basis voxel's table ("outside")
            padding = np.full(-len(surface_code) % _BLOCK, 2 * codes.shift + basis_code.max())
            surface_code = np.concatenate([surface_code, padding])
        if max(surface_code.max(), basis_code.max()) < 2**31:  # int32 halves the memory traffic
            surface_code, basis_code = surface_code.astype(np.int32), basis_code.astype(np.int32)
        n_out = t.n_groups if t.counting else self.n_bins + t.extra.shape[1]
        out = np.empty((len(basis), n_out))
        step = max(1, _CHUNK_PAIRS // max(len(surface_code), n_out + 1))  # also bounds the per-chunk histograms
        for start in range(0, len(basis), step):
            pair_codes = surface_code[None, :] - basis_code[start : start + step, None]
            entries = codes.lookup.take(pair_codes, mode="clip")  # beyond the table's ends: "outside"
            out[start : start + step] = self._count(entries) if t.counting else self._segments(entries)
        return out

    def _finish(self, out: np.ndarray) -> np.ndarray:
        """Descriptors (M, n_bins) from the votes: counts (M, n_groups) times each group's votes (counting), or
        the extended bins (M, n_bins + n_wide) with each wide row's count times its votes (segments)."""
        t = self.table
        if t.counting:
            return (t.group_votes @ out.T).T
        return out[:, : self.n_bins] + (t.extra @ out[:, self.n_bins :].T).T

    def _count(self, groups: np.ndarray) -> np.ndarray:
        """Pair counts (m, n_groups) of ``m`` basis voxels from the ``(m, N)`` groups of their pairs."""
        t = self.table
        m, n_keys = len(groups), t.n_groups + 1  # the last group is "outside the support"
        keys = groups + (np.arange(m, dtype=np.intp) * n_keys)[:, None]
        counts = np.bincount(keys.ravel(), minlength=m * n_keys).reshape(m, n_keys)
        return counts[:, :-1].astype(np.float64)

    def _segments(self, rows: np.ndarray) -> np.ndarray:
        """Extended-bin descriptors of ``m`` basis voxels from the ``(m, N)`` table rows of their pairs, with
        ``N`` a multiple of ``_BLOCK`` and the surface voxels in lexicographic order."""
        t = self.table
        m, n_rows, n_groups = len(rows), len(t.group), t.n_groups
        n_ext = self.n_bins + t.extra.shape[1]
        rows.reshape(-1, _BLOCK).sort(axis=1)  # each block's pairs by group (rows are sorted by group)
        inside = rows < n_rows  # "outside" sorts last
        counts = np.count_nonzero(inside, axis=1)
        rows = rows[inside]
        if len(rows) == 0:
            return np.zeros((m, n_ext))
        run = t.group.take(rows)  # each pair's run, (basis voxel, group), numbered in that order
        run += np.repeat(np.arange(0, m * n_groups, n_groups, dtype=np.int32), counts)
        present = np.bincount(run, minlength=m * n_groups) > 0
        first = np.flatnonzero(present)
        run = (np.cumsum(present, dtype=np.int32) - 1).take(run)
        # int32 indices: scipy takes them as they are; others cost a slow conversion
        pairs = sp.coo_array((np.ones(len(rows)), (run, rows.astype(np.int32))), shape=(len(first), n_rows))
        sums = pairs @ t.weights  # (runs, width): each run's summed slot weights, in storage order
        keys = t.group_bins.take(first % n_groups, axis=0)
        keys += (first // n_groups * (n_ext + 1))[:, None]
        totals = np.bincount(keys.ravel(), sums.ravel(), minlength=m * (n_ext + 1))
        return totals.reshape(m, n_ext + 1)[:, :n_ext]

    def describe_frames(self, frames, threads: int = 1) -> list[np.ndarray]:
        """Descriptors of many frames: ``frames`` yields ``(surface_ijk, basis_ijk)``; one array each.

        With ``threads > 1`` frames are described concurrently by a thread pool (the heavy numpy and scipy
        calls release the GIL), in order.
        """
        threads = max(1, int(threads))
        out = []
        with ThreadPoolExecutor(threads) if threads > 1 else contextlib.nullcontext() as pool:
            described = pool.map(self._describe_pair, frames) if pool else map(self._describe_pair, frames)
            for desc in described:
                out.append(desc)
                if len(out) % 100 == 0:
                    log.info("3DSC: %d frames described", len(out))
        return out

    def _describe_pair(self, frame) -> np.ndarray:
        surface, basis = frame
        return self.describe(surface, basis)


@dataclass(frozen=True, eq=False)
class _CodeTable:
    """Lookup from voxel-pair code differences to offset-table rows (or groups when counting).

    A voxel ``v`` (shifted to non-negative coordinates) has code ``v @ strides``, mixed radix with the
    ``lead`` axis most significant; the difference of two codes decodes their offset uniquely when
    every offset component is within ``reach``. Along the lead axis only offsets up to the table radius
    are tabulated (plus one "outside" entry at each end), so pair codes are clipped into the table's
    range instead of being range-checked per axis, and a voxel set of any extent along the lead axis is
    covered. "Outside" is the number of rows (groups when counting), one past the last. A pair's entry
    is ``lookup[clip(code(s) + shift - code(b))]``; entries are uint16 when they fit (half the traffic).
    """

    seen: np.ndarray  # (3,) extent the table was built for (rounded up)
    lead: int
    strides: np.ndarray  # (3,) int64
    shift: int
    lookup: np.ndarray  # (2 * shift + 1,) uint16 or int32

    def covers(self, extent) -> bool:
        return bool(all(extent[a] <= self.seen[a] for a in range(3) if a != self.lead))

    @classmethod
    def build(cls, table: OffsetTable, extent) -> "_CodeTable":
        seen = -(-np.asarray(extent, dtype=np.int64) // 8) * 8  # rounded up: fewer rebuilds
        lead, mid, low = np.argsort(seen, kind="stable")[::-1]
        reach = seen.copy()
        reach[lead] = min(reach[lead], table.radius)
        strides = np.zeros(3, dtype=np.int64)
        strides[low], strides[mid] = 1, 2 * reach[low] + 1
        strides[lead] = (2 * reach[mid] + 1) * strides[mid]
        half = int(reach @ strides)
        if 2 * half + 3 > _MAX_CODE_TABLE:
            raise VoxposeError(
                f"shape context: voxel set spans {' x '.join(str(int(e) + 1) for e in extent)} voxels, "
                "too large for the lookup table"
            )
        keep = (np.abs(table.offsets) <= reach).all(axis=1)
        values = table.group if table.counting else np.arange(len(table.offsets))
        outside = int(values[-1]) + 1
        lookup = np.full(2 * half + 3, outside, dtype=np.uint16 if outside <= np.iinfo(np.uint16).max else np.int32)
        lookup[half + 1 + table.offsets[keep] @ strides] = values[keep]
        return cls(seen=seen, lead=int(lead), strides=strides, shift=half + 1, lookup=lookup)
