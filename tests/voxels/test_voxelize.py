"""Motion -> voxel sequence: the same voxels as the direct path, translation invariance, empty frames."""

import logging

import numpy as np
import pytest

from tests.helpers import make_motion, tpose, walk_motion
from voxpose.errors import VoxposeError
from voxpose.motion.data import MotionData
from voxpose.voxels.body import body_ellipsoids
from voxpose.voxels.cameras import circular_rig
from voxpose.voxels.carve import Carver, EmptyHullError, vertical_extent
from voxpose.voxels.render import render_silhouettes
from voxpose.voxels.surface import basis_indices, surface_mask
from voxpose.voxels.voxelize import voxelize_motion, voxelize_silhouettes

RIG = circular_rig()


@pytest.fixture(scope="module")
def walk():
    return walk_motion(3)


@pytest.fixture(scope="module")
def sequence(walk):
    return voxelize_motion(walk, RIG, keep_silhouettes=True, seed=3)


def test_sequence_equals_the_direct_path(walk, sequence):
    seq = sequence
    assert seq.n_frames == 3 and not seq.empty.any() and seq.h_sub_frame == 0
    # follow_subject: the root is moved above the rig's centre, heights kept
    assert np.allclose(walk.positions[:, 0, [0, 2]] + seq.shifts[:, [0, 2]], RIG.target[[0, 2]])
    assert np.allclose(seq.shifts[:, 1], 0.0)
    el = body_ellipsoids(walk).translated(seq.shifts)
    first = render_silhouettes(el.frame(0), RIG)
    assert np.isclose(seq.h_sub, vertical_extent(Carver(RIG, 0.05)(first), 0.05))  # Section 4: l_res = 0.05 m
    assert np.isclose(seq.l_res, seq.h_sub / 60)
    for f in range(3):
        sil = render_silhouettes(el.frame(f), RIG)
        assert np.array_equal(seq.silhouettes[f], sil)
        ijk, surface, basis = seq.frame(f)
        assert np.array_equal(ijk, Carver(RIG, seq.l_res)(sil))
        assert np.array_equal(surface, surface_mask(ijk))
        on_surface = np.flatnonzero(surface)
        assert np.array_equal(basis, on_surface[basis_indices(ijk[on_surface], 200, 3)])
    counts = seq.counts()
    assert np.array_equal(counts["occupied"], np.diff(seq.offsets))
    assert all(2000 < n < 6000 for n in counts["occupied"])
    assert all(0.3 < s / n < 0.7 for s, n in zip(counts["surface"], counts["occupied"], strict=True))
    assert all(150 <= b <= 250 for b in counts["basis"])
    assert seq.ijk.dtype == np.int32 and seq.basis.dtype == np.int32


def test_follow_subject_makes_voxels_translation_invariant(walk, sequence):
    shift = np.array([2.5, 0.0, -1.7])
    moved = MotionData(
        "moved",
        "moved",
        30.0,
        walk.positions + shift,
        walk.rotations,
        walk.angles,
        walk.ends + shift,
        walk.offsets,
        walk.height,
    )
    again = voxelize_motion(moved, RIG, seed=3)
    assert np.array_equal(again.ijk, sequence.ijk) and np.array_equal(again.offsets, sequence.offsets)
    assert np.allclose(again.shifts, sequence.shifts - shift)
    # without following, frame 0 (root at the centre already) is unchanged and later frames move
    still = voxelize_motion(walk, RIG, seed=3, follow_subject=False)
    assert np.array_equal(still.frame(0)[0], sequence.frame(0)[0])
    assert not np.array_equal(still.frame(2)[0], sequence.frame(2)[0])
    assert np.allclose(still.shifts, 0.0)


def test_empty_frame_is_flagged_and_logged_not_dropped(sequence, caplog):
    frames = [sequence.silhouettes[0], np.zeros_like(sequence.silhouettes[0]), sequence.silhouettes[2]]
    with caplog.at_level(logging.INFO, logger="voxpose.voxels.voxelize"):
        seq = voxelize_silhouettes(iter(frames), RIG, seed=3, progress_every=1, name="take1")
    assert seq.empty.tolist() == [False, True, False]
    assert seq.frame(1)[0].shape == (0, 3) and seq.counts()["occupied"][1] == 0
    assert np.array_equal(seq.frame(2)[0], sequence.frame(2)[0])
    assert np.allclose(seq.shifts, 0.0) and seq.silhouettes is None
    warnings = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert any("take1: frame 1: empty visual hull" in w for w in warnings)
    progress = [r.getMessage() for r in caplog.records if "voxels," in r.getMessage()]
    assert len(progress) == 3 and progress[0].startswith("voxelize take1: frame 1/?")


def test_h_sub_from_the_first_non_empty_frame(sequence):
    empty = np.zeros_like(sequence.silhouettes[0])
    seq = voxelize_silhouettes([empty, sequence.silhouettes[1]], RIG, n_frames=2, progress_every=0)
    assert seq.h_sub_frame == 1 and seq.empty.tolist() == [True, False]
    assert np.isclose(seq.h_sub, vertical_extent(Carver(RIG, 0.05)(sequence.silhouettes[1]), 0.05))
    with pytest.raises(EmptyHullError, match="no frame has a non-empty visual hull"):
        voxelize_silhouettes([empty, empty], RIG)


@pytest.mark.parametrize("height", [1.5, 1.75, 1.95])
def test_h_sub_of_a_standing_body_is_its_height(height):
    el = body_ellipsoids(tpose(height=height)).frame(0)
    half = np.sqrt(el.shape_matrices()[:, 1, 1])  # vertical half-extent of each solid
    extent = (el.centres[:, 1] + half).max() - (el.centres[:, 1] - half).min()
    seq = voxelize_silhouettes([render_silhouettes(el, RIG)], RIG, progress_every=0)
    assert abs(seq.h_sub - extent) <= 0.05 and np.isclose(seq.l_res, seq.h_sub / 60)


def test_progress_lines_every_n_frames(caplog):
    local = np.broadcast_to(np.eye(3), (5, 14, 3, 3))
    motion = make_motion(local, np.tile([0.0, 0.98, 0.0], (5, 1)), name="still_01")
    with caplog.at_level(logging.INFO, logger="voxpose.voxels.voxelize"):
        voxelize_motion(motion, RIG, progress_every=2)
    progress = [r.getMessage() for r in caplog.records if "voxels," in r.getMessage()]
    assert [p.split(":")[1].strip() for p in progress] == ["frame 2/5", "frame 4/5"]


def test_bad_arguments(walk, sequence):
    with pytest.raises(VoxposeError, match="l_res_fraction must lie in"):
        voxelize_motion(walk, RIG, l_res_fraction=0)
    with pytest.raises(VoxposeError, match="shifts have shape"):
        voxelize_silhouettes(sequence.silhouettes, RIG, shifts=np.zeros((2, 3)))
