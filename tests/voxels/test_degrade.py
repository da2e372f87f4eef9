"""Silhouette degradations: deterministic per seed, and changing the pixels they should, by the expected amount."""

import numpy as np
import pytest

from tests.helpers import walk_motion
from voxpose.errors import VoxposeError
from voxpose.voxels.body import body_ellipsoids
from voxpose.voxels.cameras import circular_rig
from voxpose.voxels.degrade import (
    Degradation,
    boundary_band,
    drop_limb,
    flip_boundary,
    morph,
    posed_body,
    rotate_camera,
    voxelize_degraded,
)
from voxpose.voxels.render import render_silhouettes
from voxpose.voxels.voxelize import voxelize_motion

RIG = circular_rig(n=4, focal_px=280.0, width=240, image_height=240)


def discs(radius=30.0, n_views=3, size=120):
    yy, xx = np.mgrid[:size, :size]
    mask = (xx - size / 2) ** 2 + (yy - size / 2) ** 2 <= radius**2
    return np.stack([mask] * n_views)


def test_flip_changes_only_the_band_and_the_expected_fraction_of_it():
    sil = discs()
    band = np.stack([boundary_band(m, 2) for m in sil])
    # the band of a disc of radius 30 and half-width 2: the annulus 28..32, about 2 pi 30 * 4 pixels per view
    assert abs(band[0].sum() - 2 * np.pi * 30 * 4) < 0.1 * 2 * np.pi * 30 * 4
    for p in (0.1, 0.5):
        out = flip_boundary(sil, p, 2, np.random.default_rng(3))
        changed = out ^ sil
        assert not (changed & ~band).any()
        n = band.sum()
        assert abs(changed.sum() - p * n) < 5 * np.sqrt(n * p * (1 - p))  # binomial, 5 sigma


def test_degradations_are_deterministic_per_seed():
    sil = discs()
    a, b, c = (Degradation("flip", 0.3, seed).apply(7, sil, None, RIG) for seed in (1, 1, 2))
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    # a frame's draws depend on (seed, frame) alone
    assert not np.array_equal(Degradation("flip", 0.3, 1).apply(8, sil, None, RIG), a)
    r1, r2, r3 = (Degradation("calibration", 1.0, seed).carving_rig(RIG) for seed in (4, 4, 5))
    assert all(np.array_equal(x.R, y.R) for x, y in zip(r1, r2, strict=True))
    assert any(not np.array_equal(x.R, y.R) for x, y in zip(r1, r3, strict=True))


@pytest.mark.parametrize("k", [1, 2, 3])
def test_erosion_and_dilation_change_the_area_of_a_disc_as_a_disc_of_radius_r_minus_or_plus_k(k):
    radius = 30.0
    sil = discs(radius)
    area = sil[0].sum()
    for sign in (-1, 1):
        out = morph(sil, sign * k)
        expected = np.pi * (radius + sign * k) ** 2
        # a digital disc's area is within about one perimeter-pixel band of the Euclidean one
        assert abs(out[0].sum() - expected) < 2 * np.pi * (radius + k) * 0.5
        assert (out[0] <= sil[0]).all() if sign < 0 else (out[0] >= sil[0]).all()
        assert np.array_equal(out[0], out[1])
    # the fraction of pixels kept by an erosion: ((r - k) / r)^2
    assert morph(sil, -k)[0].sum() / area == pytest.approx(((radius - k) / radius) ** 2, abs=0.02)


def test_a_missing_limb_removes_its_exclusive_pixels_in_one_view():
    body = body_ellipsoids(walk_motion(1)).translated(-walk_motion(1).positions[0, 0] * [1, 0, 1]).frame(0)
    sil = render_silhouettes(body, RIG)
    previous = 0
    for level in (1, 2, 3):
        out = drop_limb(sil, body, RIG, level, np.random.default_rng(11))
        changed = out ^ sil
        views = np.flatnonzero(changed.any(axis=(1, 2)))
        assert len(views) <= 1 and not (out & ~sil).any()  # one view, pixels only removed
        removed = int(changed.sum())
        assert removed >= previous  # same draws: the same limb and view lose more segments
        previous = removed
    # independent check of the last one: render every segment alone; removed = covered by the dropped ones only
    cam = views[0]
    single = {n: render_silhouettes(_only(body, n), RIG)[cam] for n in body.names}
    dropped = [n for n in body.names if (single[n] & changed[cam]).any()]
    rest = np.any([single[n] for n in body.names if n not in dropped], axis=0)
    expect = np.any([single[n] for n in dropped], axis=0) & ~rest
    assert previous > 50 and np.array_equal(changed[cam], expect)


def _only(body, name):
    from voxpose.voxels.body import Ellipsoids

    i = body.names.index(name)
    return Ellipsoids((name,), body.centres[[i]], body.rotations[[i]], body.radii[[i]])


def test_a_rotated_camera_keeps_its_centre_and_turns_by_the_angle():
    cam = RIG[1]
    moved = rotate_camera(cam, 1.5, [0.0, 0.6, 0.8])
    assert np.allclose(moved.centre, cam.centre)
    angle = np.degrees(np.arccos((np.trace(moved.R @ cam.R.T) - 1) / 2))
    assert angle == pytest.approx(1.5)
    rig = Degradation("calibration", 0.5, 0).carving_rig(RIG)
    changed = [i for i in range(len(RIG)) if not np.allclose(rig[i].R, RIG[i].R)]
    assert len(changed) == 1


def test_clean_degraded_voxels_equal_the_plain_voxelizer():
    motion = walk_motion(3)
    args = {"l_res_fraction": 1 / 40, "n_basis": 50, "seed": 2}
    plain = voxelize_motion(motion, RIG, **args)
    clean = voxelize_degraded(motion, RIG, Degradation("none", 0, 0), **args)
    assert np.array_equal(plain.ijk, clean.ijk) and np.array_equal(plain.basis, clean.basis)
    eroded = voxelize_degraded(motion, RIG, Degradation("morph", -1, 0), **args)
    assert eroded.counts()["occupied"].sum() < plain.counts()["occupied"].sum()
    ellipsoids, shifts = posed_body(motion, RIG)
    assert np.allclose(shifts, plain.shifts) and ellipsoids.n_frames == 3


@pytest.mark.parametrize(
    "kind, level", [("blur", 1), ("flip", 1.5), ("morph", 0.5), ("limb", 4), ("calibration", 90), ("none", 1)]
)
def test_bad_degradations_are_refused(kind, level):
    with pytest.raises(VoxposeError):
        Degradation(kind, level, 0)
