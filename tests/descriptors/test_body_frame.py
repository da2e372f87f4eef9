"""Body-aligned 3D shape contexts (issue 18, item 4): the reference heading turns exactly with the world, the
resampled grid is the hull's, and descriptors of a hull turned on the grid are the unturned hull's."""

import numpy as np
import pytest

from tests.helpers import walk_motion
from voxpose import kernels
from voxpose.descriptors.body_frame import BASIS_SEED, body_voxels, continuous_headings, reference_heading
from voxpose.descriptors.lut import ShapeContextTable
from voxpose.descriptors.sequence import describe_sequence
from voxpose.descriptors.settings import DescriptorSettings
from voxpose.errors import VoxposeError
from voxpose.voxels.cameras import circular_rig
from voxpose.voxels.sequence import VoxelSequence
from voxpose.voxels.surface import basis_indices, surface_mask
from voxpose.voxels.voxelize import voxelize_motion

PATHS = ["numpy", pytest.param("numba", marks=pytest.mark.skipif(not kernels.numba_available(), reason="no numba"))]

H_SUB = 60.0
SMALL = {"n_r": 3, "n_e": 3, "n_a": 8, "r_min": 1.0, "r_max": 1 / 3}


def yaw(points, degrees):
    """Points turned about the vertical through the origin: +Z towards +X (the heading's sense)."""
    a = np.deg2rad(degrees)
    rot = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    return np.asarray(points, dtype=float) @ rot.T


def trunk(facing: float, semi=(9.0, 5.0)) -> np.ndarray:
    """Voxels of an elliptic cylinder H_SUB tall, wide (``semi[0]``) across and shallow (``semi[1]``) along the
    heading ``facing`` (degrees, 0 facing +Z), standing on y = 0, with arms held forward above the trunk band."""
    axis = np.arange(-12, 13)
    x, y, z = (c.ravel() for c in np.meshgrid(axis, np.arange(int(H_SUB)), axis, indexing="ij"))
    a = np.deg2rad(facing)
    across = x * np.cos(a) - z * np.sin(a)  # along the shoulder line (heading facing + 90)
    along = x * np.sin(a) + z * np.cos(a)  # along the facing direction
    inside = (across / semi[0]) ** 2 + (along / semi[1]) ** 2 <= 1
    arms = (y > 47) & (y < 51) & (np.abs(across) < 8) & (np.abs(across) > 5) & (along > 0) & (along < 11)
    return np.stack([x, y, z], axis=1)[inside | arms]


def test_reference_heading_turns_exactly_with_the_points():
    rng = np.random.default_rng(3)
    points = rng.normal(size=(400, 3)) * [6.0, 20.0, 3.0] + [2.0, 30.0, -1.0]
    h0, pivot = reference_heading(points, H_SUB)
    for phi in (0.0, 37.5, 90.0, 141.0, 180.0, 233.0, -300.0):
        axis = np.array([4.0, 0.0, -7.0])  # any vertical axis
        turned = yaw(points - axis, phi) + axis
        h1, pivot1 = reference_heading(turned, H_SUB)
        assert np.mod(h1 - h0 - phi + 180.0, 360.0) - 180.0 == pytest.approx(0.0, abs=1e-9)
        np.testing.assert_allclose(pivot1, yaw(pivot[None] - axis, phi)[0] + axis, atol=1e-9)


@pytest.mark.parametrize("facing", [0.0, 30.0, 72.0, 125.0, 200.0, 301.0])
def test_reference_heading_of_a_trunk_is_its_facing_direction(facing):
    """Front and back told apart; the axis within 3 degrees (a 9 x 5 voxel ellipse on the grid)."""
    h0, _ = reference_heading(trunk(facing), H_SUB)
    assert np.mod(h0 - facing + 180.0, 360.0) - 180.0 == pytest.approx(0.0, abs=3.0)


def test_body_voxels_at_zero_heading_are_the_hull_translated():
    ijk = trunk(30.0) + [3, 0, -2]
    body, surface, body_basis = body_voxels(ijk, 30, 0.0, (3.25, 0.0, -1.75))
    shift = body.min(axis=0) - ijk.min(axis=0)
    assert {tuple(v) for v in body - shift} == {tuple(v) for v in ijk}
    np.testing.assert_array_equal(surface, surface_mask(body))
    np.testing.assert_array_equal(body_basis, body[surface][basis_indices(body[surface], 30, BASIS_SEED)])


def test_body_voxels_at_90_degrees_are_the_hull_turned_on_the_grid():
    ijk = trunk(30.0)
    body, _, _ = body_voxels(ijk, 30, 90.0, (0.0, 0.0, 0.0))
    expected = np.rint(yaw(ijk, -90.0)).astype(int)
    assert {tuple(v) for v in body} == {tuple(v) for v in expected}


def resampled_cell_by_cell(ijk, h0, pivot):
    """Brute-force reference of the turned grid: every cell of the turned hull's box (one cell of margin),
    its centre turned back and rounded to the voxel it falls in, kept when that voxel is occupied; cells in
    x, y, z order."""
    pivot = np.array([pivot[0], 0.0, pivot[2]])
    turned = yaw(ijk - pivot, -h0)
    low, high = np.floor(turned.min(axis=0)) - 1, np.ceil(turned.max(axis=0)) + 1
    axes = [np.arange(lo, hi + 1) for lo, hi in zip(low, high, strict=True)]
    cells = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3).astype(np.int64)
    source = np.rint(yaw(cells, h0) + pivot).astype(np.int64)
    occupied = {tuple(v) for v in ijk}
    return cells[[tuple(v) in occupied for v in source]]


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("h0", [0.0, 17.3, 90.0, 141.0, 233.7, 359.9])
def test_body_voxels_are_the_cell_by_cell_resampling(h0, path, monkeypatch):
    """The column-wise resampling (numpy path and compiled kernel) gives the cells, in the order, of turning
    every cell of the box back."""
    monkeypatch.setenv(kernels.ENV, path)
    ijk = trunk(55.0) + [7, 3, -4]
    for pivot in [(7.0, 0.0, -4.0), (9.4, 0.0, -1.7)]:
        body, surface, _ = body_voxels(ijk, 30, h0, pivot)
        expected = resampled_cell_by_cell(ijk, h0, pivot)
        np.testing.assert_array_equal(body, expected)
        np.testing.assert_array_equal(surface, surface_mask(expected))


@pytest.mark.skipif(not kernels.numba_available(), reason="numba is not installed: numpy path only")
def test_the_kernel_resamples_carved_hulls_as_the_numpy_path(monkeypatch):
    """On carved walking hulls at their own and at arbitrary headings, pivots off the grid: the same voxels,
    surface and basis, bit for bit (the kernel repeats the numpy path's arithmetic)."""
    seq = voxelize_motion(walk_motion(6), circular_rig(), progress_every=0)
    rng = np.random.default_rng(3)
    for f in range(seq.n_frames):
        ijk = seq.frame(f)[0]
        h0, pivot = reference_heading(ijk, seq.h_sub / seq.l_res)
        for heading in (h0, *rng.uniform(0.0, 360.0, 3), 45.0, 270.0):
            shifted = pivot + rng.normal(scale=0.3, size=3) * [1, 0, 1]
            out = {}
            for path in ("numba", "numpy"):
                monkeypatch.setenv(kernels.ENV, path)
                out[path] = body_voxels(ijk, 40, heading, shifted)
            for fast, slow in zip(out["numba"], out["numpy"], strict=True):
                assert fast.dtype == slow.dtype
                np.testing.assert_array_equal(fast, slow)


def sequence(frames) -> VoxelSequence:
    """A voxel sequence of the given frames (occupied voxels), every 20th surface voxel a basis voxel."""
    surfaces = [surface_mask(f) for f in frames]
    bases = [np.flatnonzero(s)[::20] for s in surfaces]
    return VoxelSequence(l_res=1.0, h_sub=H_SUB, h_sub_frame=0, ijk=np.concatenate(frames).astype(np.int32),
                         offsets=np.cumsum([0] + [len(f) for f in frames]), surface=np.concatenate(surfaces),
                         basis=np.concatenate(bases).astype(np.int32),
                         basis_offsets=np.cumsum([0] + [len(b) for b in bases]),
                         empty=np.zeros(len(frames), dtype=bool), shifts=np.zeros((len(frames), 3)))  # fmt: skip


def test_world_frame_is_the_table_on_the_grid_as_before():
    ijk = trunk(30.0)
    seq = sequence([ijk])
    descriptors, h0 = describe_sequence(seq, DescriptorSettings(**SMALL), n_basis=30)
    _, surface, basis = seq.frame(0)
    np.testing.assert_array_equal(descriptors[0], ShapeContextTable(H_SUB, **SMALL).describe(ijk[surface], ijk[basis]))
    assert np.array_equal(h0, [0.0])


def test_body_frame_descriptors_of_a_hull_turned_on_the_grid_are_the_same():
    """Turned by 90 degrees the hull is the same voxels, its h0 90 degrees further (30 -> 120),
    and the basis voxels drawn on the turned grid the same: the body-frame descriptors agree, the world-frame
    ones do not."""
    ijk = trunk(30.0) + [5, 0, 2]
    turned = np.rint(yaw(ijk, 90.0)).astype(int)  # exact on the grid
    seq = sequence([ijk, turned])
    body, h0 = describe_sequence(seq, DescriptorSettings(**SMALL, frame="body"), n_basis=30)
    assert h0[1] - h0[0] == pytest.approx(90.0, abs=1e-9)
    np.testing.assert_allclose(body[1], body[0], rtol=1e-12, atol=1e-12)
    world, _ = describe_sequence(seq, DescriptorSettings(**SMALL), n_basis=30)
    assert np.abs(world[1] - world[0]).max() > 0.1


def test_frame_is_world_or_body_and_names_the_descriptor_folder():
    assert DescriptorSettings().tag() == "R0.3333-r2-4x5x10-soft"
    assert DescriptorSettings(frame="body").tag() == "R0.3333-r2-4x5x10-soft-body"
    with pytest.raises(VoxposeError, match="frame must be one of world, body"):
        DescriptorSettings.from_config({"frame": "camera"})


def sense_track(n=120, seed=0):
    """A planted heading track turning 200 degrees over ``n`` frames: axes (either sense, with 1 degree noise),
    scores voting for the true sense with magnitudes 0.2-1, and the truth."""
    rng = np.random.default_rng(seed)
    truth = np.mod(40.0 + np.linspace(0.0, 200.0, n), 360.0)
    flip = rng.random(n) < 0.5  # the axis is reported in either sense
    axes = truth + 180.0 * flip + rng.normal(0.0, 1.0, n)
    scores = rng.uniform(0.2, 1.0, n) * np.where(flip, -1.0, 1.0)
    return axes, scores, truth


def angle_error(a, b):
    return np.abs(np.mod(np.asarray(a) - b + 180.0, 360.0) - 180.0)


def test_continuous_headings_undo_isolated_and_short_flips():
    axes, scores, truth = sense_track()
    scores[[5, 40, 41, 42, 90]] *= -0.5  # the votes point backwards on five frames (one run of three)
    scores[:2] *= -1.0  # and on the first two
    alone = np.array([continuous_headings([a], [s], [0])[0] for a, s in zip(axes, scores, strict=True)])
    assert (angle_error(alone, truth) > 135).sum() == 7  # what the per-frame rule does
    headings = continuous_headings(axes, scores, np.arange(len(axes)))
    assert angle_error(headings, truth).max() < 5.0


def test_continuous_headings_follow_a_long_run_of_votes():
    axes, scores, truth = sense_track(seed=1)
    scores[:70] *= -1.0  # the first 70 frames vote backwards: more than a few frames, so they are followed
    headings = continuous_headings(axes, scores, np.arange(len(axes)))
    assert (angle_error(headings[:70], truth[:70] + 180.0) < 5.0).all()
    assert (angle_error(headings[70:], truth[70:]) < 5.0).all()


def test_an_axis_swinging_by_90_degrees_does_not_lock_the_sense():
    """A crouched hull's axis swings by 90 degrees and back: the votes keep deciding, before and after."""
    axes, scores, truth = sense_track(seed=3)
    axes[50:60] += 90.0  # ten frames whose axis lies across the body: their senses are each vote's
    headings = continuous_headings(axes, scores, np.arange(len(axes)))
    outside = np.r_[0:50, 60 : len(axes)]
    assert angle_error(headings[outside], truth[outside]).max() < 5.0


def test_continuous_headings_turn_with_the_world():
    axes, scores, _ = sense_track(seed=2)
    scores[[10, 11, 60]] *= -1.0
    frames = np.arange(len(axes))
    base = continuous_headings(axes, scores, frames)
    for phi in (37.5, 90.0, 180.0, 301.0):
        assert angle_error(continuous_headings(axes + phi, scores, frames), base + phi).max() < 1e-9


def test_a_gap_unlinks_the_frames_around_it():
    """Across a gap the votes decide alone: a true about-turn while the subject was out of view is kept; linked,
    the weaker votes give way."""
    axes = np.array([10.0, 11.0, 12.0, 190.0, 191.0, 192.0])
    scores = np.array([1.0, 1.0, 1.0, 0.5, 0.5, 0.5])
    linked = continuous_headings(axes, scores, [0, 1, 2, 3, 4, 5])
    unlinked = continuous_headings(axes, scores, [0, 1, 2, 40, 41, 42])
    assert angle_error(unlinked, axes).max() < 1e-9
    assert angle_error(linked[:3], axes[:3]).max() < 1e-9 and angle_error(linked[3:], axes[3:] - 180).max() < 1e-9
