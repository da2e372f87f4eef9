"""Shape from silhouettes (Section 4): the visual hull on a world-aligned voxel grid, carved coarse to fine.

Grid: voxel ``(i, j, k)`` (int32) is the cube of side ``l_res`` metres centred at ``(ijk + 0.5) * l_res``.
A voxel is occupied when its centre projects inside the silhouette of every camera, or of at least
``min_views`` cameras for noisy real silhouettes. A centre belongs to the pixel whose square contains
its projection (``voxpose.voxels.cameras``: pixel centres at integer coordinates); a centre that projects
outside an image or lies behind a camera counts as outside that silhouette.

Where to look. ``bounds`` (a box in metres) limits the voxels considered to those whose centres lie
inside it. By default the box is the rig's capture volume: the bounding box of the region inside the
viewing frusta of at least ``min_views`` cameras (the hull cannot reach outside it), found by linear
programs over the frusta's half-spaces and cached per rig. Inside it the silhouettes are back-projected
coarse to fine, as an octree: cells of 2^k x 2^k x 2^k voxels, the coarsest about a quarter of the box's
longest side. For each cell and camera, a pixel window bounds the projections of all the voxel centres
in the cell: a sphere of radius ``rho`` around them projects within ``rho |a - u p3| / (z - rho |p3|)``
of the centre's projection ``u`` (``a`` and ``p3`` the first and third rows of ``P``, ``z`` the depth),
and likewise in ``v``. A silhouette's summed-area table counts its pixels in the window: a cell with
none in more than ``C - min_views`` cameras is dropped, a cell whose window is all silhouette in at
least ``min_views`` cameras is kept whole, any other cell is split into 8; single voxels are tested at
their centres. The windows are conservative, so the result is exactly that of testing every voxel of the
box (``tests/voxels/test_carve.py`` checks it); only the work shrinks.

Lens distortion. A rig with distorted cameras is carved through its pinhole twin (``voxpose.voxels.lens``):
the octree's windows are straight-line projections on the twin's canvas, and each frame's silhouettes are
looked up there twice, dilated and eroded by one pixel (3 x 3) in the real image first: the lookup moves a
point by less than a real pixel in each coordinate, so a twin window's pixels in the dilated lookup bound
those a cell may hold and in the eroded lookup those it surely holds. Single voxels are then tested at their
true distorted projections, so the result is that of testing every voxel centre at the real pixel holding its
distorted projection (``tests/voxels/test_lens.py`` checks it). An undistorted rig is carved exactly as before.

Speed. The summed-area tables, the cells' windows and the voxel tests run as numba kernels
(``voxpose.voxels.carve_kernels``) when ``voxpose.kernels`` selects them: the same arithmetic on the same
projections, so the same voxels, 1.7 - 2.2x faster (``benchmarks/bench_predict.py``'s carve stage).

An empty hull (silhouettes that do not intersect) gives an empty (0, 3) array, which the caller reports
per frame; ``voxels.voxelize`` raises ``EmptyHullError`` when no frame has a hull to measure h_sub on.
"""

import functools
import itertools
import math

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.kernels import use_numba
from voxpose.voxels import carve_kernels
from voxpose.voxels.cameras import Rig
from voxpose.voxels.capture_volume import polytope_box
from voxpose.voxels.lens import pinhole_twin
from voxpose.voxels.morphology import dilate, erode

_MAX_SUBSETS = 1000
_SQUARE = np.ones((3, 3), dtype=bool)  # a window's one-pixel margin (dilated and eroded twins)
_COARSE_CELLS = 4  # the coarsest octree level has about this many cells along the box's longest side
_capture_cache: dict = {}


class EmptyHullError(VoxposeError):
    """The silhouettes of a frame have no common voxel (nothing to measure or describe)."""


def _frustum_halfspaces(rig: Rig) -> np.ndarray:
    """(C, 4, 4) rows ``w`` with ``w . (X, 1) >= 0`` for points X projecting inside each image."""
    height, width = rig.image_size
    rows = []
    for p in rig.projections:
        rows.append([p[0] + 0.5 * p[2], (width - 0.5) * p[2] - p[0], p[1] + 0.5 * p[2], (height - 0.5) * p[2] - p[1]])
    return np.array(rows)


def capture_bounds(rig: Rig, min_views: int | None = None) -> np.ndarray:
    """(2, 3) box (min, max corners, metres) of the points seen by at least ``min_views`` cameras.

    The union over every ``min_views``-subset of cameras of the bounding box of their frusta's
    intersection (``voxels.capture_volume.polytope_box``); cached per rig. A subset whose frusta do not bound a
    region (parallel views, ``min_views=1``) is an error asking for explicit ``bounds``.
    """
    k = len(rig) if min_views is None else int(min_views)
    if rig.distorted:
        rig = pinhole_twin(rig).rig  # the twin's frusta hold every ray the real images see
    key = (tuple((c.P.tobytes(), c.width, c.height) for c in rig.cameras), k)
    if key in _capture_cache:
        return _capture_cache[key].copy()
    n_subsets = math.comb(len(rig), k)
    if n_subsets > _MAX_SUBSETS:
        raise VoxposeError(f"carve: {n_subsets} camera subsets for min_views={k}; pass bounds= explicitly")
    planes = _frustum_halfspaces(rig)
    box = np.array([[np.inf] * 3, [-np.inf] * 3])
    for subset in itertools.combinations(range(len(rig)), k):
        rows = planes[list(subset)].reshape(-1, 4)
        corners = polytope_box(-rows[:, :3], rows[:, 3])
        if corners is None:
            raise VoxposeError(
                f"carve: the views of rig {rig.name} do not bound a capture volume for min_views={k}; "
                "pass bounds= explicitly"
            )
        box[0] = np.minimum(box[0], corners[0])
        box[1] = np.maximum(box[1], corners[1])
    _capture_cache[key] = box
    return box.copy()


def _check_silhouettes(silhouettes, rig: Rig) -> np.ndarray:
    sil = np.asarray(silhouettes)
    expected = (len(rig),) + rig.image_size
    if sil.shape != expected:
        raise VoxposeError(f"carve: silhouettes have shape {sil.shape}, rig {rig.name} needs {expected}")
    if sil.dtype != bool:
        raise VoxposeError(f"carve: silhouettes must be boolean masks, got dtype {sil.dtype}")
    return sil


class Carver:
    """Visual-hull carving for one rig and voxel size, reusable over frames (``carver(silhouettes)``).

    Parameters
    ----------
    rig : the calibrated cameras, in silhouette order.
    l_res : voxel side in metres.
    min_views : a voxel is occupied if inside at least this many silhouettes (default: all).
    bounds : (2, 3) box (min, max corners, metres) for the voxel centres; default ``capture_bounds``.
    """

    def __init__(self, rig: Rig, l_res: float, *, min_views: int | None = None, bounds=None):
        if not (isinstance(l_res, int | float | np.floating) and np.isfinite(l_res) and l_res > 0):
            raise VoxposeError(f"carve: l_res must be a positive number of metres, got {l_res!r}")
        n_cams = len(rig)
        if min_views is None:
            min_views = n_cams
        if isinstance(min_views, bool) or not isinstance(min_views, int | np.integer):
            raise VoxposeError(f"carve: min_views must be an integer, got {min_views!r}")
        if not 1 <= min_views <= n_cams:
            raise VoxposeError(f"carve: min_views must lie in 1..{n_cams} for rig {rig.name}, got {min_views}")
        box = capture_bounds(rig, min_views) if bounds is None else np.asarray(bounds, dtype=float)
        if box.shape != (2, 3) or not np.isfinite(box).all() or (box[1] < box[0]).any():
            raise VoxposeError("carve: bounds must be finite [[xmin, ymin, zmin], [xmax, ymax, zmax]]")
        self.rig = rig
        self._twin = pinhole_twin(rig) if rig.distorted else None
        if self._twin is not None:
            rig = self._twin.rig
        self.l_res = float(l_res)
        self.min_views = int(min_views)
        self.lo = np.ceil(box[0] / self.l_res - 0.5).astype(np.int64)
        self.hi = np.floor(box[1] / self.l_res - 0.5).astype(np.int64)  # inclusive
        proj = rig.projections  # (C, 3, 4)
        extent = int(np.max(self.hi - self.lo + 1)) if (self.hi >= self.lo).all() else 0
        self.levels = max(0, math.ceil(math.log2(max(extent, 1) / _COARSE_CELLS)))
        side = 2**self.levels
        counts = -(-(self.hi - self.lo + 1) // side)
        self._coarse = np.argwhere(np.ones(np.maximum(counts, 0), dtype=bool)).astype(np.int64)
        # homogeneous image coordinates of voxel centres: ((lo + g + 0.5) l_res, 1) -> _gain @ g + _bias,
        # rows ordered (row r of P, camera c) -> r * C + c
        self._gain = self.l_res * proj[:, :, :3].transpose(1, 0, 2).reshape(-1, 3)
        origin = np.append((self.lo + 0.5) * self.l_res, 1.0)
        self._bias = (proj @ origin).T.reshape(-1, 1)
        # |a - u p3|^2 = |a|^2 - 2 u a.p3 + u^2 |p3|^2 for the window bound (a, p3: rows of P)
        rows = proj[:, :, :3]
        self._aa, self._ap, self._bb, self._bp, self._pp = (
            np.einsum("ci,ci->c", rows[:, i], rows[:, j])[:, None] for i, j in ((0, 0), (0, 2), (1, 1), (1, 2), (2, 2))
        )
        self._p3norm = np.sqrt(self._pp)
        self._window_terms = tuple(t.ravel() for t in (self._p3norm, self._aa, self._ap, self._bb, self._bp, self._pp))

    def _project(self, grid):
        """Pixel coordinates and depths (C, N) of the points ``(lo + grid + 0.5) * l_res``, grid (N, 3)."""
        h = self._gain @ grid.T
        h += self._bias
        n_cams = len(self.rig)
        x, y, z = h[:n_cams], h[n_cams : 2 * n_cams], h[2 * n_cams :]
        with np.errstate(divide="ignore", invalid="ignore"):
            return x / z, y / z, z

    def _cell_views(self, cells, side, tables, full_tables):
        """For each cell (N,): cameras whose silhouette (``tables``) may hold one of its voxel centres, and
        cameras whose silhouette (``full_tables``) surely holds all of them."""
        flat, base, offsets, limits = tables
        rho = 0.5 * math.sqrt(3.0) * (side - 1) * self.l_res
        u, v, z = self._project(cells * float(side) + 0.5 * (side - 1))
        if use_numba():  # the same arithmetic in one loop (voxpose.voxels.carve_kernels)
            full_flat, full_base, full_offsets, full_limits = full_tables
            return carve_kernels.cell_views(u, v, z, rho, *self._window_terms, flat, base.ravel(), offsets, limits,
                                            full_tables is tables, full_flat, full_base.ravel(), full_offsets,
                                            full_limits, len(self.rig) - self.min_views)  # fmt: skip
        near = z - rho * self._p3norm
        front = near > 0
        scale = rho / np.where(front, near, 1.0)
        u = np.where(front, u, 0.0)  # a cell reaching behind a camera may hold a centre of any view
        v = np.where(front, v, 0.0)
        ru = scale * np.sqrt(np.maximum(self._aa - 2 * u * self._ap + u * u * self._pp, 0))
        rv = scale * np.sqrt(np.maximum(self._bb - 2 * v * self._bp + v * v * self._pp, 0))
        # window of pixel rows r0..r1-1 and columns c0..c1-1 (image), then clipped to each crop
        c0 = u0 = np.floor(u - ru + 0.5)
        c1 = u1 = np.floor(u + ru + 1.5)
        r0 = v0 = np.floor(v - rv + 0.5)
        r1 = v1 = np.floor(v + rv + 1.5)
        area = (c1 - c0) * (r1 - r0)
        c0, c1 = (_clamp(c - offsets[:, 1:], limits[:, 1:]) for c in (c0, c1))
        r0, r1 = (_clamp(r - offsets[:, :1], limits[:, :1]) for r in (r0, r1))
        stride = limits[:, 1:] + 1
        r0 = r0 * stride + base
        r1 = r1 * stride + base
        hits = flat[r1 + c1] - flat[r0 + c1] - flat[r1 + c0] + flat[r0 + c0]
        maybe = ((hits > 0) | ~front).sum(axis=0)
        if full_tables is not tables:
            flat, base = full_tables[:2]
            full_offsets, full_limits = full_tables[2:]
            c0, c1 = (_clamp(c - full_offsets[:, 1:], full_limits[:, 1:]) for c in (u0, u1))
            r0, r1 = (_clamp(r - full_offsets[:, :1], full_limits[:, :1]) for r in (v0, v1))
            stride = full_limits[:, 1:] + 1
            r0, r1 = r0 * stride + base, r1 * stride + base
            hits = flat[r1 + c1] - flat[r0 + c1] - flat[r1 + c0] + flat[r0 + c0]
        full = ((hits == area) & front).sum(axis=0)
        return maybe, full

    def _voxel_occupied(self, grid, sil):
        """(N,) bool: voxel centres ``(lo + grid + 0.5) * l_res`` inside at least ``min_views`` silhouettes.

        Camera by camera, each on the voxels still undecided: a voxel outside more than ``C - min_views``
        silhouettes is dropped (measured 2.7x faster than testing every camera on every voxel: most voxels
        tested here lie just outside the hull and fail early).
        """
        n_cams, height, width = sil.shape
        u, v, z = self._project(grid.astype(float))
        if self._twin is not None:  # the real (distorted) projection, on the twin's pinhole coordinates
            u, v = self._twin.distort_pixels(u, v)
        images = sil.reshape(n_cams, -1)
        if use_numba():  # the same tests in one loop (voxpose.voxels.carve_kernels)
            return carve_kernels.voxel_occupied(u, v, z, images, width, height, n_cams - self.min_views)
        alive = np.arange(len(grid))
        misses = np.zeros(len(grid), dtype=np.int64)
        for cam in range(n_cams):
            with np.errstate(invalid="ignore"):
                col = np.floor(u[cam, alive] + 0.5)
                row = np.floor(v[cam, alive] + 0.5)
            inside = (z[cam, alive] > 0) & (col >= 0) & (col < width) & (row >= 0) & (row < height)
            index = np.where(inside, row * width + col, 0).astype(np.int64)
            misses[alive[~(images[cam].take(index) & inside)]] += 1
            alive = alive[misses[alive] <= n_cams - self.min_views]
        occupied = np.zeros(len(grid), dtype=bool)
        occupied[alive] = True
        return occupied

    def __call__(self, silhouettes) -> np.ndarray:
        """Occupied voxels (N, 3) int32 of one frame's silhouettes (C, H, W) bool."""
        sil = _check_silhouettes(silhouettes, self.rig)
        if self._twin is None:
            tables = full_tables = _summed_areas(sil)
        else:  # conservative twins: a cell's pixels there bound its pixels in the real images (module docstring)
            tables = _summed_areas(self._twin.to_twin(dilate(sil, _SQUARE)))
            full_tables = _summed_areas(self._twin.to_twin(erode(sil, _SQUARE)))
            if full_tables is None:
                full_tables = _NO_PIXELS(len(sil))
        if len(self._coarse) == 0 or tables is None:
            return np.zeros((0, 3), dtype=np.int32)
        if np.count_nonzero(tables[3][:, 0] > 0) < self.min_views:
            return np.zeros((0, 3), dtype=np.int32)
        span = self.hi - self.lo
        cells = self._coarse
        done = []  # voxels (grid offsets from lo) of cells found wholly inside the hull
        for level in range(self.levels, 0, -1):
            side = 2**level
            maybe, full = self._cell_views(cells, side, tables, full_tables)
            inside = full >= self.min_views
            if inside.any():
                voxels = (cells[inside, None, :] * side + _block(side)[None]).reshape(-1, 3)
                done.append(voxels[_within(voxels, span)])
            cells = cells[(maybe >= self.min_views) & ~inside]
            cells = (2 * cells[:, None, :] + _CHILDREN[None]).reshape(-1, 3)
            cells = cells[_within(cells, span)]
        done.append(cells[self._voxel_occupied(cells, sil)])
        return (np.concatenate(done) + self.lo).astype(np.int32)


_CHILDREN = np.array(list(itertools.product((0, 1), repeat=3)), dtype=np.int64)


@functools.cache
def _block(side: int) -> np.ndarray:
    """(side^3, 3) voxel offsets of a cell of ``side`` voxels, in C order (read-only: cached)."""
    block = np.argwhere(np.ones((side,) * 3, dtype=bool))
    block.flags.writeable = False
    return block


def _clamp(x, high):
    """``x`` clipped to ``0 .. high`` as int64 (``np.minimum``/``np.maximum``: faster than ``np.clip`` here)."""
    return np.minimum(np.maximum(x, 0), high).astype(np.int64)


def _within(grid, span):
    """Rows of ``grid`` (N, 3) inside ``0 .. span`` on every axis (non-negative by construction): three
    column comparisons, several times faster than ``(grid <= span).all(axis=1)``."""
    return (grid[:, 0] <= span[0]) & (grid[:, 1] <= span[1]) & (grid[:, 2] <= span[2])


def _NO_PIXELS(n_cams):  # noqa: N802 (a table constructor)
    """Summed-area tables of empty silhouettes (``_summed_areas`` layout)."""
    zeros = np.zeros((n_cams, 2), dtype=np.int64)
    return np.zeros(n_cams, dtype=np.int32), np.arange(n_cams)[:, None], zeros, zeros.copy()


def _summed_areas(sil: np.ndarray):
    """Summed-area tables of every silhouette, each cropped to its bounding box, in one flat array.

    Returns ``(flat, base, offsets, limits)``: camera c's table ``T`` (``T[r, k]`` counts the pixels of
    the crop's rows < r and columns < k) starts at ``flat[base[c]]`` with row stride ``limits[c, 1] + 1``;
    ``offsets[c]`` is the crop's (row, col) in the image and ``limits[c]`` its (rows, cols). An empty
    silhouette gets a 1 x 1 zero table (``limits`` 0). ``None`` when every silhouette is empty.
    """
    rows_any = sil.any(axis=2)
    cols_any = sil.any(axis=1)
    if not rows_any.any():
        return None
    n_cams = sil.shape[0]
    offsets = np.zeros((n_cams, 2), dtype=np.int64)
    limits = np.zeros((n_cams, 2), dtype=np.int64)
    for c in range(n_cams):
        rows = np.flatnonzero(rows_any[c])
        if rows.size:
            cols = np.flatnonzero(cols_any[c])
            offsets[c] = rows[0], cols[0]
            limits[c] = rows[-1] + 1 - rows[0], cols[-1] + 1 - cols[0]
    sizes = (limits[:, 0] + 1) * (limits[:, 1] + 1)
    base = np.cumsum(sizes) - sizes
    if use_numba():  # the same sums in one pass (voxpose.voxels.carve_kernels)
        flat = np.zeros(int(sizes.sum()), dtype=np.int32)
        carve_kernels.summed_areas_fill(sil, offsets, limits, base, flat)
        return flat, base[:, None], offsets, limits
    pieces = []
    for c in range(n_cams):
        if not limits[c].any():
            pieces.append(np.zeros(1, dtype=np.int32))
            continue
        (r0, c0), (n_rows, n_cols) = offsets[c], limits[c]
        crop = sil[c, r0 : r0 + n_rows, c0 : c0 + n_cols]
        table = np.zeros((crop.shape[0] + 1, crop.shape[1] + 1), dtype=np.int32)
        np.cumsum(crop, axis=0, dtype=np.int32, out=table[1:, 1:])
        np.cumsum(table[1:, 1:], axis=1, out=table[1:, 1:])
        pieces.append(table.reshape(-1))
    return np.concatenate(pieces), base[:, None], offsets, limits


def vertical_extent(ijk, l_res: float) -> float:
    """Height (metres) of the occupied voxel cubes ``ijk`` (N >= 1, 3): ``(j_max - j_min + 1) * l_res``.

    How ``voxels.voxelize`` measures h_sub (Section 4). The extent of the cubes is unbiased: the number of grid
    centres inside an interval is its length over ``l_res`` on average, whereas the extent of the centres,
    ``(j_max - j_min) * l_res``, is short by one voxel on average.
    """
    return float((ijk[:, 1].max() - ijk[:, 1].min() + 1) * l_res)
