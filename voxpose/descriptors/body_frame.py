"""A body-aligned frame for the 3D shape contexts: descriptors that do not turn with the world (issue 18, item 4).

The paper aligns the descriptor's frame with the world (Section 4, first bullet), so that the descriptors see
the body heading. They then see which way the world's axes point too: turning the world about the vertical
changes every descriptor, and a regressor recognises only the headings its training frames cover. With
``descriptor.frame: body`` each frame is described in a frame of its own hull instead:

1. a reference heading ``h0`` is read off the hull by an estimator that turns exactly with the world. Its axis:
   the orientation of the horizontal second moments of the occupied voxels at trunk height, ``H_BAND`` (a
   fraction of the subject height ``h_sub``) above their vertical centroid, weighted by a Hann window in
   height so that voxels enter and leave the band gently. With ``c = dz + i dx`` (``dx``, ``dz`` from the
   band's weighted centroid, so ``arg c`` is the heading of the direction, 0 along +Z and 90 along +X as in
   ``voxpose.motion.canon``), ``m2 = sum w c^2`` turns by ``2 phi`` when the world turns by ``phi``; the
   trunk is wider than deep, so its major axis is the shoulder line and ``arg(m2) / 2 + 90`` the facing
   direction, modulo 180. Its sense: the one along which the hull leans forward, by the score
   ``skew + HEAD_WEIGHT * head / h_sub``, with ``skew`` the normalised third moment along the axis of the voxels
   above the hull's centroid and ``head`` the mean offset along it of the top ``HEAD_BAND`` of the hull, both
   about the band's centroid (head, arms and chest lean forward of the trunk; the score changes sign with the
   axis, so the choice turns with the world too). Measured on the default generated motions at l_res =
   h_sub / 60 (every third frame of the 9 Table 1 motions, 1130 frames): the sense matched the true facing in
   99.2 % of frames (jumps 99.2 %), against 97.4 % for the skew alone (jumps 91.5 %), 95.1 % for the head
   alone and 98.4 - 98.7 % with head weights 5, 20 or 40; on fewer frames (200) the skew alone beat the trunk
   band's own skew (86.0 %), the whole hull's (72.0 %) and the feet's offset from the shins (71.5 %). A
   modulo-180 reference alone turns the frame by 180 degrees whenever the world turns by 180, and the
   regressor's front/back calls then decide the heading: the rotation test failed with it. In a sequence the
   senses are chosen together (``continuous_headings``): a hull does not turn about (by more than ``FLIP``)
   from one frame to the next, which undoes short runs of frames whose own score points backwards;
2. the occupied voxels are resampled on a grid turned by ``h0`` about the vertical through the band's
   centroid (nearest neighbour: a cell of the turned grid is occupied when the voxel its centre falls in
   is), surface voxels are found again on it (``voxels.surface.surface_mask``) and the basis voxels are
   turned and rounded onto it. Heights are not touched, so the resampling is exact at ``h0`` = 0 and 90;
   the lookup-table path (``descriptors.lut``) then describes the turned grid as any other;
3. the regressor learns the 39 angles and the heading relative to ``h0`` (``regression.pose_encoding``)
   and ``h0`` is added back to its estimate.

Turning the world by ``phi`` then turns ``h0`` by ``phi`` (exactly, for points; up to the voxel grid for
carved hulls) and leaves the turned grid's contents, hence the descriptors and the 39 angles, the same up
to the grid: the rotation test of ``voxpose.apply.world_rotation`` (numbers in ``benchmarks/heading_rotation.py``).

On the embedded default's Table 1 (MPPCA + MVRVM, 418 test frames) the body frame gave full body 3.18 deg against
4.54 in the world frame and heading 21.0 against 23.1 deg RMS, the heading error then being six frames whose sense
came out backwards (errors > 135 deg; 4.5 deg RMS on the other 412 frames, median 3.7, against 20.4 and 9.6).
On Table 2 (1410 test frames): full body 3.75 against 6.15 deg, heading 23.4 against 37.4 deg RMS, 23 against 51
flips (7.4 against 21.2 deg RMS without them). Choosing the senses over the sequence (``continuous_headings``)
then took the wrong senses on the default's circle6 hulls from 42 to 3 of 3578 frames, Table 1 to 2.7 deg full
body and 4.3 deg heading, Table 2 to 3.2 deg (default run, ``snakemake --cores 2``, README tables). On the shared
real walks the per-frame sense is wrong on 22 % (Bandai) and 27 % (CMU) of the frames in long stretches (the axis
swings by +-30-48 deg with the gait), and over the sequence on 25 % and 23 %: the sense cue, not its temporal
choice, fails there. So with ``features.heading_sense: density`` (the default) the feature model, which knows
the training bodies seen from the front, chooses the senses afterwards (``voxpose.features.heading_sense``); the
cue here still turns the grid the descriptors are taken on.
"""

import numpy as np

from voxpose.descriptors import body_frame_kernels
from voxpose.kernels import use_numba
from voxpose.voxels.surface import basis_indices, surface_mask

H_BAND = 0.25
"""Height of the trunk band above the hull's vertical centroid, as a fraction of ``h_sub``: from the lower
trunk to below the shoulders on the body model (the centroid sits near the pelvis)."""


HEAD_BAND = 0.12
"""Top of the hull (fraction of ``h_sub``) whose offset along the axis votes for the sense: the head."""

HEAD_WEIGHT = 10.0
"""Weight of the head's offset (in units of ``h_sub``) against the upper body's normalised skew (module docstring)."""

FLIP = 135.0
"""Degrees between the reference headings of consecutive frames counted as a front/back flip."""

SWITCH = 5.0
"""Cost of a flip between consecutive frames, in units of the sequence's median sense score."""

BASIS_SEED = 0
"""Seed of the basis voxels' grid offset in the body frame (``voxels.surface.basis_indices``): the cells are
anchored to the pivot, so they stay on the same parts of the body whichever way the world's axes point."""


def reference_heading(points, h_sub_voxels: float) -> tuple[float, np.ndarray]:
    """``(h0, pivot)`` of a hull: the facing direction in degrees in [0, 360) (module docstring) and the
    trunk band's weighted centroid (3,) (its height the hull's centroid height), in the points' units.

    ``points`` (N, 3) are voxel indices or centres in voxel units, Y up; ``h_sub_voxels`` the subject height
    in the same units. Turning the points by ``phi`` about any vertical axis turns ``h0`` by ``phi``.
    """
    axis, score, pivot = heading_axis(points, h_sub_voxels)
    return float(continuous_headings([axis], [score], [0])[0]), pivot


def heading_axis(points, h_sub_voxels: float) -> tuple[float, float, np.ndarray]:
    """``(axis, score, pivot)``: the facing axis in degrees (one of its two senses), the sense score (positive:
    the hull leans forward along ``axis``) and the pivot, before the sense is chosen (module docstring)."""
    p = np.asarray(points, dtype=np.float64)
    y0 = p[:, 1].mean()
    band = H_BAND * float(h_sub_voxels)
    s = (p[:, 1] - y0) / band
    w = np.where((s > 0) & (s < 1), np.sin(np.pi * s) ** 2, 0.0)
    if w.sum() == 0:  # a hull flatter than the band (never a standing body): the whole hull
        w = np.ones(len(p))
    centre = w @ p / w.sum()
    c = (p[:, 2] - centre[2]) + 1j * (p[:, 0] - centre[0])
    m2 = np.sum(w * c * c)
    facing = np.angle(m2) / 2 + np.pi / 2
    along = (c * np.exp(-1j * facing)).real
    upper = along[p[:, 1] > y0]
    skew = np.mean(upper**3) / max(np.mean(upper**2) ** 1.5, np.finfo(float).tiny) if len(upper) else 0.0
    head = along[p[:, 1] > p[:, 1].max() - HEAD_BAND * float(h_sub_voxels)].mean()
    score = float(skew + HEAD_WEIGHT * head / float(h_sub_voxels))
    return float(np.rad2deg(facing)), score, np.array([centre[0], y0, centre[2]])


def continuous_headings(axes, scores, frames) -> np.ndarray:
    """Reference headings (degrees in [0, 360)) of a sequence, each frame's sense chosen with its neighbours.

    Per frame the hull gives an axis (``axes``, degrees, either sense) and a sense score (``scores``); alone,
    the sign of the score picks the sense, and on about 1 % of frames it picks the back (module docstring).
    A person does not turn about between two consecutive frames (at 30 frames/s a turn of ``FLIP`` = 135
    degrees would be 4000 deg/s), so the senses of a sequence are chosen together by dynamic programming
    (Viterbi over the two senses per frame), minimising the total ``|score|`` of the frames whose sense goes
    against their own score plus ``SWITCH`` x the median ``|score|`` for every turn of more than ``FLIP``
    degrees between consecutive frames (``frames``: the frame numbers; frames further apart, across a gap,
    are not linked). A run of a few frames voting backwards inside a sequence that faces one way is so
    undone, while a long run of confident votes is followed. Where the axis itself swings by about 90 degrees
    (a crouched or jumping hull whose trunk looks round), both senses turn by about 90 degrees, neither is
    penalised and the scores decide: the generated jumps showed that a rule linking such frames locks onto the
    wrong sense. Turning the world by ``phi`` turns every result by ``phi``, as each axis turns and the scores
    keep their signs.
    """
    axes, scores, frames = (np.asarray(a, dtype=float) for a in (axes, scores, frames))
    n = len(axes)
    if n == 0:
        return np.zeros(0)
    headings = axes[:, None] + np.array([0.0, 180.0])  # (n, 2): the two senses
    against = np.abs(scores)[:, None] * np.stack([scores < 0, scores >= 0], axis=1)  # cost of each sense
    jump = SWITCH * max(float(np.median(np.abs(scores))), np.finfo(float).tiny)
    cost, back = against[0].copy(), np.zeros((n, 2), dtype=np.int64)
    for k in range(1, n):
        turn = np.abs((headings[k][None, :] - headings[k - 1][:, None] + 180.0) % 360.0 - 180.0)  # (prev, cur)
        linked = frames[k] - frames[k - 1] == 1
        step = cost[:, None] + jump * ((turn > FLIP) & linked)
        back[k] = np.argmin(step, axis=0)
        cost = step[back[k], [0, 1]] + against[k]
    sense = np.empty(n, dtype=np.int64)
    sense[-1] = int(np.argmin(cost))
    for k in range(n - 1, 0, -1):
        sense[k - 1] = back[k, sense[k]]
    return np.mod(headings[np.arange(n), sense], 360.0)


def _cos_sin(degrees: float) -> np.ndarray:
    """``(cos, sin)`` of a turn by ``degrees`` (shared by both paths, so that they turn by the same numbers)."""
    a = np.deg2rad(degrees)
    return np.array([np.cos(a), np.sin(a)])


def _yaw(points, degrees: float) -> np.ndarray:
    """Points (N, 3) turned by ``degrees`` about the vertical through the origin (``Ry``: +Z towards +X)."""
    cos, sin = _cos_sin(degrees)
    x, z = points[:, 0], points[:, 2]
    return np.stack([cos * x + sin * z, points[:, 1], -sin * x + cos * z], axis=1)


def body_voxels(ijk, n_basis: int, h0: float, pivot) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A frame's voxels in its body frame: (occupied (N', 3), surface (N',) bool, basis (B, 3)) int64 on the
    grid turned by ``h0`` degrees about the vertical through ``pivot`` (module docstring, step 2), in the
    order of the turned grid's cells (x, then y, then z).

    The turn leaves heights alone, so each column (x, z) of the turned grid is turned back once and takes
    the whole column of the source grid it falls in: the same rounding of the same numbers as turning every
    cell of the box back, hence the same voxels (tested against that); the body frame's description fell from
    10.1-11.5 to 6.9-8.0 ms per frame (``benchmarks/bench_body_frame.py``). The compiled kernel
    (``body_frame_kernels``, selected by ``voxpose.kernels``) does the same in one loop.
    """
    ijk = np.asarray(ijk, dtype=np.int64)
    if use_numba() and len(ijk):
        body, surface = body_frame_kernels.turned_voxels(ijk, _cos_sin(-h0), _cos_sin(h0), float(pivot[0]),
                                                         float(pivot[2]))  # fmt: skip
    else:
        body = _turned_voxels(ijk, h0, pivot)
        surface = surface_mask(body)
    return body, surface, body[surface][basis_indices(body[surface], n_basis, BASIS_SEED)]


def _turned_voxels(ijk, h0: float, pivot) -> np.ndarray:
    """The numpy path of ``body_voxels``: the occupied cells of the turned grid (N', 3), in its order."""
    pivot = np.array([pivot[0], 0.0, pivot[2]])
    turned = _yaw(ijk - pivot, -h0)
    low = np.floor(turned.min(axis=0)).astype(np.int64) - 1
    high = np.ceil(turned.max(axis=0)).astype(np.int64) + 1
    xs, ys, zs = (np.arange(lo, hi + 1) for lo, hi in zip(low, high, strict=True))
    columns = np.stack(np.meshgrid(xs, [0], zs, indexing="ij"), axis=-1).reshape(-1, 3)
    source = np.rint(_yaw(columns, h0) + pivot).astype(np.int64)
    origin = ijk.min(axis=0)
    size = ijk.max(axis=0) - origin + 1
    sx, sz, sy = source[:, 0] - origin[0], source[:, 2] - origin[2], ys - origin[1]
    inside = (sx >= 0) & (sx < size[0]) & (sz >= 0) & (sz < size[2])
    rows = (sy >= 0) & (sy < size[1])
    local = ijk - origin
    grid = np.zeros((size[0], size[2], size[1]), dtype=bool)  # (x, z, y): a column is contiguous
    grid[local[:, 0], local[:, 2], local[:, 1]] = True
    occupied = np.zeros((len(columns), len(ys)), dtype=bool)
    occupied[np.ix_(inside, rows)] = grid[sx[inside], sz[inside]][:, sy[rows]]
    i, j, k = np.nonzero(occupied.reshape(len(xs), len(zs), len(ys)).transpose(0, 2, 1))
    return np.stack([xs[i], ys[j], zs[k]], axis=1)
