"""3D shape contexts, reference definition: known bins, boundaries, symmetries, invariances, bad input."""

import math

import numpy as np
import pytest

from voxpose.descriptors.settings import DescriptorSettings
from voxpose.descriptors.shape_context import BinGeometry, shape_contexts
from voxpose.errors import VoxposeError

L_RES = 0.03  # metres; with H_SUB the support is R_min = 2, R_max = 20 voxels as in the paper
H_SUB = 1.8
N_R, N_E, N_A = 4, 5, 10


def radii(i, n_r=N_R, r_min=2.0, r_max=20.0):
    """Eq. 4 written out independently: R_i = R_min (R_max / R_min)^(i / n_r), voxels."""
    return r_min * (r_max / r_min) ** (i / n_r)


def bin_weight(i_r, i_e, n_r=N_R, n_e=N_E, n_a=N_A, r_min=2.0, r_max=20.0):
    """1 / cbrt(V) of a bin of the sphere, V in voxels: shell volume times solid-angle fraction."""
    shell = (radii(i_r + 1, n_r, r_min, r_max) ** 3 - radii(i_r, n_r, r_min, r_max) ** 3) / 3
    band = math.cos(math.pi * i_e / n_e) - math.cos(math.pi * (i_e + 1) / n_e)
    return (shell * band * 2 * math.pi / n_a) ** (-1 / 3)


def direction(theta_deg, phi_deg):
    """Unit vector at elevation theta from +Y and azimuth phi from +X towards +Z."""
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return np.array([math.sin(t) * math.cos(p), math.cos(t), math.sin(t) * math.sin(p)])


def describe_offsets(offsets_vox, soft, centre=(0.4, 1.1, -0.3), **params):
    """Descriptor at ``centre`` (metres) of points at the given offsets in voxels."""
    centre = np.asarray(centre)
    points = centre + np.asarray(offsets_vox, dtype=float).reshape(-1, 3) * L_RES
    return shape_contexts(points, centre[None], l_res=L_RES, h_sub=H_SUB, soft=soft, **params)[0]


def index(i_r, i_e, i_a, n_e=N_E, n_a=N_A):
    return (i_r * n_e + i_e) * n_a + i_a


def bin_centre_offset(i_r, i_e, i_a):
    """Offset (voxels) at the centre of a bin in log-r, elevation and azimuth."""
    r = radii(i_r + 0.5)
    return r * direction((i_e + 0.5) * 180 / N_E, (i_a + 0.5) * 360 / N_A)


@pytest.mark.parametrize("soft", [False, True])
@pytest.mark.parametrize("bin_", [(0, 0, 0), (1, 2, 3), (2, 4, 9), (3, 1, 5), (3, 3, 7)])
def test_point_at_bin_centre_lands_in_that_bin(bin_, soft):
    got = describe_offsets(bin_centre_offset(*bin_), soft)
    assert np.flatnonzero(got).tolist() == [index(*bin_)]
    assert got[index(*bin_)] == pytest.approx(bin_weight(bin_[0], bin_[1]), rel=1e-12)


@pytest.mark.parametrize(
    "theta, phi, i_e, i_a",
    [
        (90, 90, 2, 2),  # +Z is azimuth 90 degrees: sector [72, 108)
        (90, 10, 2, 0),  # just off +X towards +Z
        (90, 350, 2, 9),  # just off +X towards -Z
        (90, 200, 2, 5),  # -X side
        (20, 100, 0, 2),  # near the zenith
        (170, 300, 4, 8),  # near the nadir, -Z side
    ],
)
def test_angle_conventions_hard(theta, phi, i_e, i_a):
    got = describe_offsets(radii(1.5) * direction(theta, phi), soft=False)
    assert np.flatnonzero(got).tolist() == [index(1, i_e, i_a)]


@pytest.mark.parametrize("soft", [False, True])
@pytest.mark.parametrize("up, i_e", [(1, 0), (-1, N_E - 1)])
def test_vertical_axis_spreads_over_azimuth(up, i_e, soft):
    got = describe_offsets([0.0, up * radii(2.5), 0.0], soft).reshape(N_R, N_E, N_A)
    expected = np.zeros((N_R, N_E, N_A))
    expected[2, i_e, :] = bin_weight(2, i_e) / N_A
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("soft", [False, True])
def test_support_is_r_min_inclusive_r_max_exclusive(soft):
    along = direction(90, 90)  # centre of elevation sector 2 and azimuth sector 2: no angular split
    assert describe_offsets(along * 2.0, soft)[index(0, 2, 2)] == pytest.approx(bin_weight(0, 2), rel=1e-12)
    assert not describe_offsets(along * (2.0 - 1e-6), soft).any()
    assert not describe_offsets(along * 20.0, soft).any()
    assert describe_offsets(along * (20.0 - 1e-6), soft)[index(3, 2, 2)] == pytest.approx(bin_weight(3, 2))
    assert not describe_offsets([0.0, 0.0, 0.0], soft).any()  # the centre never votes


def test_hard_boundary_goes_to_upper_bin():
    # radial boundary R_1, elevation boundary 36 degrees, azimuth boundary 72 degrees
    assert np.flatnonzero(describe_offsets(radii(1) * direction(54, 90), soft=False)).tolist() == [index(1, 1, 2)]
    assert np.flatnonzero(describe_offsets(radii(1.5) * direction(36, 90), soft=False)).tolist() == [index(1, 1, 2)]
    assert np.flatnonzero(describe_offsets(radii(1.5) * direction(90, 72), soft=False)).tolist() == [index(1, 2, 2)]


@pytest.mark.parametrize(
    "offset, split",
    [
        (radii(2) * direction(54, 90), [(1, 1, 2), (2, 1, 2)]),  # radial boundary R_2
        (radii(1.5) * direction(108, 90), [(1, 2, 2), (1, 3, 2)]),  # elevation boundary 108 degrees
        (radii(1.5) * direction(90, 144), [(1, 2, 3), (1, 2, 4)]),  # azimuth boundary 144 degrees
        (radii(1.5) * direction(90, 0), [(1, 2, 9), (1, 2, 0)]),  # azimuth 0 = 360: wraps
    ],
)
def test_soft_vote_on_boundary_splits_equally(offset, split):
    got = describe_offsets(offset, soft=True)
    expected = np.zeros_like(got)
    for b in split:
        expected[index(*b)] = 0.5 * bin_weight(b[0], b[1])
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-12)


def test_soft_vote_interpolates_linearly_in_log_radius():
    # a quarter bin above the centre of shell 1, angles at a bin centre: 3/4 to shell 1, 1/4 to shell 2
    got = describe_offsets(radii(1.75) * direction(54, 90), soft=True)
    expected = np.zeros_like(got)
    expected[index(1, 1, 2)] = 0.75 * bin_weight(1, 1)
    expected[index(2, 1, 2)] = 0.25 * bin_weight(2, 1)
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-12)


def test_soft_vote_clamps_at_the_radial_ends():
    # inside the innermost half-shell and the outermost one, all mass stays in the end shell
    for t_r, shell in [(0.2, 0), (3.8, 3)]:
        got = describe_offsets(radii(t_r) * direction(54, 90), soft=True)
        assert np.flatnonzero(got).tolist() == [index(shell, 1, 2)]
        assert got[index(shell, 1, 2)] == pytest.approx(bin_weight(shell, 1), rel=1e-12)


def random_cloud(seed, n_points=300, n_centres=12):
    rng = np.random.default_rng(seed)
    points = rng.normal(scale=0.25, size=(n_points, 3)) + [0.1, 1.0, -0.2]
    return points, points[rng.choice(n_points, n_centres, replace=False)]


def rotate_about_y(points, angle_deg, pivot):
    """Rotate so that azimuth atan2(z, x) grows by angle_deg about a vertical axis through pivot."""
    a = math.radians(angle_deg)
    rot = np.array([[math.cos(a), 0, -math.sin(a)], [0, 1, 0], [math.sin(a), 0, math.cos(a)]])
    return (points - pivot) @ rot.T + pivot


@pytest.mark.parametrize("soft", [False, True])
def test_rotation_by_one_sector_shifts_azimuth_bins(soft):
    points, centres = random_cloud(1)
    pivot = np.array([0.3, 0.0, 0.5])
    before = shape_contexts(points, centres, l_res=L_RES, h_sub=H_SUB, soft=soft)
    after = shape_contexts(
        rotate_about_y(points, 36, pivot),
        rotate_about_y(centres, 36, pivot),
        l_res=L_RES,
        h_sub=H_SUB,
        soft=soft,
    )
    shifted = np.roll(before.reshape(-1, N_R, N_E, N_A), 1, axis=3).reshape(before.shape)
    assert before.sum() > 100  # the clouds fill the supports
    np.testing.assert_allclose(after, shifted, rtol=1e-9, atol=1e-12)
    assert not np.allclose(after, before)


@pytest.mark.parametrize("soft", [False, True])
def test_translation_and_scale_invariance(soft):
    points, centres = random_cloud(2)
    base = shape_contexts(points, centres, l_res=L_RES, h_sub=H_SUB, soft=soft)
    moved = shape_contexts(points + [3.2, -1.1, 7.5], centres + [3.2, -1.1, 7.5], l_res=L_RES, h_sub=H_SUB, soft=soft)
    scaled = shape_contexts(points * 1.7, centres * 1.7, l_res=L_RES * 1.7, h_sub=H_SUB * 1.7, soft=soft)
    np.testing.assert_allclose(moved, base, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(scaled, base, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("soft", [False, True])
def test_votes_conserve_mass(soft):
    points, centres = random_cloud(3)
    got = shape_contexts(points, centres, l_res=L_RES, h_sub=H_SUB, soft=soft)
    weights = np.array([bin_weight(r, e) for r in range(N_R) for e in range(N_E) for _ in range(N_A)])
    distance = np.linalg.norm(points[None] - centres[:, None], axis=2) / L_RES
    in_support = ((distance >= 2.0) & (distance < 20.0)).sum(axis=1)
    np.testing.assert_allclose((got / weights).sum(axis=1), in_support, rtol=1e-12)


def test_descriptors_are_rotation_dependent():
    # the frame is the world frame (Section 4, first bullet): a quarter turn about X changes descriptors
    points, centres = random_cloud(4)
    quarter = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    a = shape_contexts(points, centres, l_res=L_RES, h_sub=H_SUB)
    b = shape_contexts(points @ quarter.T, centres @ quarter.T, l_res=L_RES, h_sub=H_SUB)
    assert np.abs(a - b).max() > 0.1


def test_grid_offsets_on_boundaries_are_decided_exactly():
    # voxel centres at a non-round voxel size: offsets (2,0,0) (r = R_min), (6,2,0) (r^2 = 40 = R_2^2 at
    # the defaults), (-3,0,0) (azimuth 180 degrees, a sector boundary) sit exactly on boundaries
    l_res = 1.75 / 60
    centre = np.array([[10, 20, 5]])
    hard = {}
    for offset in [(2, 0, 0), (6, 2, 0), (-3, 0, 0)]:
        points = (centre + offset + 0.5) * l_res
        hard[offset] = shape_contexts(points, (centre + 0.5) * l_res, l_res=l_res, h_sub=1.75, soft=False)[0]
    # theta = 90 degrees is the centre of elevation sector 2; (6,2,0) has theta = 71.57 degrees
    assert np.flatnonzero(hard[(2, 0, 0)]).tolist() == [index(0, 2, 0)]
    assert np.flatnonzero(hard[(6, 2, 0)]).tolist() == [index(2, 1, 0)]
    assert np.flatnonzero(hard[(-3, 0, 0)]).tolist() == [index(0, 2, 5)]
    points = (centre + (6, 2, 0) + 0.5) * l_res
    soft = shape_contexts(points, (centre + 0.5) * l_res, l_res=l_res, h_sub=1.75, soft=True)[0]
    weights = np.array([bin_weight(r, e) for r in range(N_R) for e in range(N_E) for _ in range(N_A)])
    per_shell = (soft / weights).reshape(N_R, -1).sum(axis=1)
    np.testing.assert_allclose(per_shell, [0.0, 0.5, 0.5, 0.0], atol=1e-12)


def test_normalise_divides_by_the_sum():
    points, centres = random_cloud(5)
    far = centres[:1] + 10.0  # no point within its support
    raw = shape_contexts(points, np.vstack([centres, far]), l_res=L_RES, h_sub=H_SUB)
    norm = shape_contexts(points, np.vstack([centres, far]), l_res=L_RES, h_sub=H_SUB, normalise=True)
    np.testing.assert_allclose(norm[:-1], raw[:-1] / raw[:-1].sum(axis=1, keepdims=True), rtol=1e-12)
    assert not norm[-1].any()


def test_bin_geometry_follows_eq4():
    g = BinGeometry.from_settings(DescriptorSettings(), 60)  # the paper's: 4 x 5 x 10, R_min 2 voxels, R_max h/3
    np.testing.assert_allclose(g.radial_boundaries, [radii(i) for i in range(5)], rtol=1e-12)
    assert g.bin_volumes.sum() == pytest.approx(4 / 3 * math.pi * (20**3 - 2**3), rel=1e-12)
    assert g.n_bins == 200


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"points": np.zeros((0, 3))}, "points is empty"),
        ({"centres": np.zeros((0, 3))}, "centres is empty"),
        ({"points": np.zeros((5, 2))}, "points must have shape"),
        ({"points": [[0, 0, np.nan]]}, "points row 0 is not finite"),
        ({"centres": [[0, 0, 0], [np.inf, 0, 0]]}, "centres row 1 is not finite"),
        ({"points": [["a", "b", "c"]]}, "points must be an (N, 3) array of numbers"),
        ({"l_res": 0.0}, "l_res must be positive"),
        ({"l_res": -0.03}, "l_res must be positive"),
        ({"h_sub": float("nan")}, "h_sub must be positive"),
        ({"r_min": 0.0}, "r_min must be positive"),
        ({"r_max": -1.0}, "r_max must be positive"),
        ({"r_min": 20.0}, "must be smaller than R_max"),
        ({"r_min": 25.0}, "must be smaller than R_max"),
        ({"n_r": 0}, "n_r must be an integer >= 1"),
        ({"n_e": 2.5}, "n_e must be an integer >= 1"),
        ({"n_a": True}, "n_a must be an integer >= 1"),
    ],
)
def test_bad_input_raises(kwargs, message):
    args = {"points": np.zeros((3, 3)), "centres": np.ones((2, 3)), "l_res": L_RES, "h_sub": H_SUB}
    args.update(kwargs)
    with pytest.raises(VoxposeError, match=message.replace("(", r"\(").replace(")", r"\)")):
        shape_contexts(args.pop("points"), args.pop("centres"), **args)
