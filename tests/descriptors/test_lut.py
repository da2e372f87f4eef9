"""Lookup-table fast path: equal to the reference on voxel centres, for many parameter sets and layouts."""

import numpy as np
import pytest

from voxpose import kernels
from voxpose.descriptors import lut as lut
from voxpose.descriptors.lut import ShapeContextTable, offset_table
from voxpose.descriptors.shape_context import shape_contexts
from voxpose.errors import VoxposeError


@pytest.fixture(autouse=True)
def numpy_path(monkeypatch):
    """These tests pin the numpy path (the reference implementation of the fast path); the compiled kernel is
    compared with it in test_lut_kernels.py."""
    monkeypatch.setenv(kernels.ENV, "numpy")


L_RES = 1.75 / 60  # a voxel size with no exact binary form, as in the paper's l_res = h_sub / 60


def reference(surface, basis, h_sub_voxels=60.0, **params):
    """The reference on voxel centres, in metres."""
    return shape_contexts(
        (np.asarray(surface) + 0.5) * L_RES,
        (np.asarray(basis) + 0.5) * L_RES,
        l_res=L_RES,
        h_sub=h_sub_voxels * L_RES,
        **params,
    )


def grid(surface, basis, h_sub_voxels=60.0, **params):
    """The fast path on one frame: a fresh table (the offset table is cached per parameter set)."""
    return ShapeContextTable(h_sub_voxels, **params).describe(surface, basis)


def blob(seed, n_surface=500, n_basis=25, size=34):
    """Random voxel set: a noisy shell of a sphere plus scattered voxels, basis partly off the surface."""
    rng = np.random.default_rng(seed)
    direction = rng.normal(size=(n_surface, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    shell = np.rint(size / 2 + direction * rng.uniform(6, size / 2, size=(n_surface, 1))).astype(int)
    scatter = rng.integers(-5, size + 5, size=(n_surface // 5, 3))
    surface = np.unique(np.vstack([shell, scatter]), axis=0) - 7
    basis = np.vstack([surface[rng.choice(len(surface), n_basis - 5, replace=False)], rng.integers(0, size, (5, 3))])
    return surface, basis


PARAMS = [
    {},
    {"n_r": 2},
    {"n_r": 6},
    {"r_max": 0.25},
    {"h_sub_voxels": 45.5},
    {"n_e": 4, "n_a": 8},  # sector boundaries at 90 degrees of elevation and at every axis
    {"n_e": 1, "n_a": 1, "r_min": 1.5},  # one sector: no row spreads over azimuth
    {"r_min": 3.0, "r_max": 0.2, "h_sub_voxels": 70.0},
]


@pytest.mark.parametrize("soft", [False, True])
@pytest.mark.parametrize("params", PARAMS, ids=lambda p: ",".join(f"{k}={v}" for k, v in p.items()) or "paper")
def test_lut_equals_reference(params, soft):
    params = dict(params)
    h_sub_voxels = params.pop("h_sub_voxels", 60.0)
    surface, basis = blob(sum(map(ord, str(params))) + soft)
    fast = grid(surface, basis, h_sub_voxels=h_sub_voxels, soft=soft, **params)
    ref = reference(surface, basis, h_sub_voxels, soft=soft, **params)
    distance = np.linalg.norm(surface[None] - basis[:, None], axis=2)
    r_max = params.get("r_max", 1 / 3) * h_sub_voxels
    assert ((distance >= params.get("r_min", 2.0)) & (distance < r_max)).sum(axis=1).mean() > 100
    np.testing.assert_allclose(fast, ref, rtol=0, atol=1e-9)


# every kind of exact boundary at the paper's parameters: R_min (r = 2), R_2 (r^2 = 40), R_max (r = 20,
# on the axis and off it), elevation 90 degrees in the middle of a sector, azimuth 0 and 180 degrees,
# the vertical axis, the centre itself
BOUNDARY_OFFSETS = [
    (2, 0, 0),
    (0, 2, 0),
    (0, -2, 0),
    (6, 2, 0),
    (-6, 0, 2),
    (0, 2, -6),
    (20, 0, 0),
    (12, 16, 0),
    (0, -12, 16),
    (19, 0, 0),
    (-3, 0, 0),
    (0, 0, 0),
    (1, 1, 1),
]


@pytest.mark.parametrize("soft", [False, True])
def test_lut_equals_reference_on_boundary_offsets(soft):
    basis = np.array([[30, 40, 20]])
    surface = basis + BOUNDARY_OFFSETS
    np.testing.assert_allclose(
        grid(surface, basis, h_sub_voxels=60, soft=soft),
        reference(surface, basis, soft=soft),
        rtol=0,
        atol=1e-12,
    )
    outside = basis + [(20, 0, 0), (12, 16, 0), (0, -12, 16), (0, 0, 0), (1, 1, 0)]
    assert not grid(outside, basis, h_sub_voxels=60, soft=soft).any()


@pytest.mark.parametrize("soft", [False, True])
def test_far_voxels_and_wide_extents(soft):
    # voxels far beyond the support along every axis, which the code table must clip, not alias
    surface, basis = blob(11)
    far = np.array([[200, 0, 0], [0, 150, 0], [0, 0, 120], [-90, 5, 7], [3, -130, 2], [41, 41, 41]])
    surface = np.vstack([surface, far, far + [2, 3, 1]])
    basis = np.vstack([basis, far[:2]])
    np.testing.assert_allclose(
        grid(surface, basis, h_sub_voxels=60, soft=soft),
        reference(surface, basis, soft=soft),
        rtol=0,
        atol=1e-9,
    )


def test_grid_translation_invariance_and_duplicates():
    surface, basis = blob(12)
    table = ShapeContextTable(60)
    base = table.describe(surface, basis)
    np.testing.assert_array_equal(table.describe(surface - [500, -70, 3], basis - [500, -70, 3]), base)
    doubled = table.describe(np.vstack([surface, surface[:40]]), basis)  # a repeated voxel votes twice
    np.testing.assert_allclose(doubled, reference(np.vstack([surface, surface[:40]]), basis), atol=1e-9)
    assert np.abs(doubled - base).max() > 0.01


@pytest.mark.parametrize("threads", [1, 2])
def test_describe_frames_matches_single_frames_across_many_extents(threads):
    table = ShapeContextTable(60, soft=True)
    frames = []
    for seed in [*range(11), 3, 0]:  # extents growing, then shrinking: the code table grows and is reused
        surface, basis = blob(seed, n_surface=120 + 30 * seed, n_basis=8, size=20 + 4 * seed)
        frames.append((surface, basis))
    batch = table.describe_frames(iter(frames), threads=threads)
    assert len(batch) == len(frames)
    for (surface, basis), got in zip(frames, batch, strict=True):
        np.testing.assert_allclose(got, reference(surface, basis), atol=1e-9)
    assert table._codes.covers(np.ptp(np.vstack(frames[10]), axis=0))


def test_code_table_too_large_when_grown_falls_back_to_each_frame():
    # long thin frames along each axis in turn: one table covering all would exceed the size limit
    table = ShapeContextTable(60, soft=False)
    surface, basis = blob(17, n_surface=150, n_basis=6)
    for axis in range(3):
        far = np.zeros((2, 3), dtype=int)
        far[:, axis] = [1500, 1503]
        frame_surface = np.vstack([surface, far])
        got = table.describe(frame_surface, np.vstack([basis, far[:1]]))
        np.testing.assert_allclose(got, reference(frame_surface, np.vstack([basis, far[:1]]), soft=False), atol=1e-9)
        assert got[-1].sum() > 0  # the far pair (3 voxels apart) votes


@pytest.mark.parametrize("soft", [False, True])
def test_normalised_descriptors_are_the_reference_divided_by_its_sum(soft):
    surface, basis = blob(13)
    got = grid(surface, basis, n_r=3, soft=soft, normalise=True)
    raw = reference(surface, basis, n_r=3, soft=soft)
    assert (raw.sum(axis=1) > 0).all() and not np.allclose(raw.sum(axis=1), 1.0)
    np.testing.assert_allclose(got, raw / raw.sum(axis=1, keepdims=True), atol=1e-12)


def test_table_is_cached_per_parameter_set():
    a, b = ShapeContextTable(60), ShapeContextTable(60.0)
    assert a.table is b.table
    assert ShapeContextTable(45).table.radius == 15  # R_max = 45 / 3 voxels
    assert ShapeContextTable(60).table.radius == 20
    assert offset_table(a.geometry, True) is a.table
    assert a.table.counting is False and ShapeContextTable(60, soft=False).table.counting is True


@pytest.mark.parametrize(
    "surface, basis, kwargs, message",
    [
        (np.zeros((0, 3), int), np.zeros((2, 3), int), {}, "surface_ijk is empty"),
        (np.zeros((4, 3), int), np.zeros((0, 3), int), {}, "basis_ijk is empty"),
        (np.zeros((4, 2), int), np.zeros((2, 3), int), {}, "surface_ijk must have shape"),
        (np.zeros((4, 3)), np.zeros((2, 3), int), {}, "surface_ijk must hold integer voxel indices"),
        ([[0, 0, 0], [1, np.nan, 2]], np.zeros((2, 3), int), {}, "surface_ijk row 1 is not finite"),
        (np.zeros((4, 3), int), [[np.inf, 0, 0]], {}, "basis_ijk row 0 is not finite"),
        (np.zeros((4, 3), int), np.zeros((2, 3), int), {"h_sub_voxels": 0}, "h_sub / l_res must be positive"),
        (np.zeros((4, 3), int), np.zeros((2, 3), int), {"h_sub_voxels": -60}, "h_sub / l_res must be positive"),
        (np.zeros((4, 3), int), np.zeros((2, 3), int), {"r_min": 0.0}, "r_min must be positive"),
        (np.zeros((4, 3), int), np.zeros((2, 3), int), {"r_min": -2.0}, "r_min must be positive"),
        (np.zeros((4, 3), int), np.zeros((2, 3), int), {"r_max": 0.0}, "r_max must be positive"),
        (np.zeros((4, 3), int), np.zeros((2, 3), int), {"r_max": -0.3}, "r_max must be positive"),
        (np.zeros((4, 3), int), np.zeros((2, 3), int), {"r_max": float("nan")}, "r_max must be positive"),
        (np.zeros((4, 3), int), np.zeros((2, 3), int), {"n_a": 0}, "n_a must be an integer >= 1"),
        (np.zeros((4, 3), int), np.zeros((2, 3), int), {"r_min": 30}, "must be smaller than R_max"),
        ([[0, 0, 0], [4000, 4000, 4000]], [[0, 0, 0]], {}, "too large for the lookup table"),
        (
            [[0, 0, 0]],
            [[0, 0, 0]],
            {"h_sub_voxels": 2.5, "r_min": 0.5},
            "no voxel offset lies in the support",
        ),
    ],
)
def test_bad_input_raises(surface, basis, kwargs, message):
    kwargs = {"h_sub_voxels": 60, **kwargs}
    with pytest.raises(VoxposeError, match=message.replace("(", r"\(")):
        grid(surface, basis, **kwargs)


@pytest.mark.parametrize("soft", [False, True])
def test_chunked_basis_equals_one_pass(soft, monkeypatch):
    surface, basis = blob(14)
    monkeypatch.setattr(lut, "_CHUNK_PAIRS", 3 * len(surface))  # three basis voxels per chunk
    chunked = grid(surface, basis, h_sub_voxels=60, soft=soft)
    np.testing.assert_allclose(chunked, reference(surface, basis, soft=soft), rtol=0, atol=1e-9)


@pytest.mark.parametrize("soft", [False, True])
def test_quarter_turn_on_the_grid_shifts_azimuth_by_two_of_eight_sectors(soft):
    # (x, y, z) -> (-z, y, x) turns azimuth by exactly 90 degrees on the grid, where many offsets sit on
    # the 45-degree sector boundaries and on the vertical axis
    surface, basis = blob(15)
    turn = np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]])
    params = {"h_sub_voxels": 60, "n_e": 4, "n_a": 8, "soft": soft}
    before = grid(surface, basis, **params).reshape(len(basis), 4, 4, 8)
    after = grid(surface @ turn.T, basis @ turn.T, **params).reshape(len(basis), 4, 4, 8)
    np.testing.assert_allclose(after, np.roll(before, 2, axis=3), rtol=0, atol=1e-12)
    assert np.abs(after - before).max() > 0.1


@pytest.mark.parametrize("soft", [False, True])
@pytest.mark.parametrize(
    "h_sub_voxels, r_max",
    [
        (60, 0.333333333333),  # as written in config.yaml: R_max a hair below 20 voxels
        (1.93 / (1.93 / 60), 1 / 3),  # h_sub / l_res = 60.00000000000001: R_max a hair above 20
        (60, 0.3333333333334),
    ],
)
def test_rounded_parameters_keep_boundary_decisions(h_sub_voxels, r_max, soft):
    # R_max and R_2 a hair from the grid's r = 20 and r^2 = 40: snapping decides those offsets as for the exact
    # parameters (r = 20 never votes, r^2 = 40 goes to shell 2)
    basis = np.array([[30, 40, 20]])
    surface = np.vstack([basis + BOUNDARY_OFFSETS, blob(16)[0] + [20, 30, 10]])
    exact = reference(surface, basis, soft=soft)  # the direct definition at the exact parameters (h/3, 60 voxels)
    rounded = grid(surface, basis, h_sub_voxels=h_sub_voxels, r_max=r_max, soft=soft)
    np.testing.assert_allclose(rounded, exact, rtol=1e-9, atol=1e-9)
    on_r_max = basis + [(20, 0, 0), (12, 16, 0), (0, -12, 16)]
    assert not grid(on_r_max, basis, h_sub_voxels=h_sub_voxels, r_max=r_max, soft=soft).any()


def test_soft_votes_do_not_depend_on_surface_order_or_block_size(monkeypatch):
    """Each run of a basis voxel's pairs is summed in ascending table-row order whatever the order of the
    surface voxels and the sort blocks (lut module docstring), so the descriptors agree bit for bit."""
    surface, basis = blob(21, n_surface=1500, n_basis=60)
    surface = np.vstack([surface, surface[:7]])  # repeated voxels too
    table = ShapeContextTable(60, soft=True)
    base = table.describe(surface, basis)
    np.testing.assert_allclose(base, reference(surface, basis, soft=True), rtol=0, atol=1e-9)
    shuffled = surface[np.random.default_rng(0).permutation(len(surface))]
    np.testing.assert_array_equal(table.describe(shuffled, basis), base)
    monkeypatch.setattr(lut, "_BLOCK", 8)  # many blocks, the last one padded
    np.testing.assert_array_equal(table.describe(shuffled, basis), base)


def test_a_groups_table_rows_are_in_lexicographic_order_of_their_offsets():
    table = ShapeContextTable(60, soft=True).table
    for g in np.unique(table.group)[::7]:
        offsets = table.offsets[table.group == g]
        order = np.lexsort(offsets.T[::-1])
        np.testing.assert_array_equal(order, np.arange(len(offsets)))
