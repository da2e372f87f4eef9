"""Surface voxels against known shapes and a brute-force neighbour check; basis down-sampling, by the numpy path
and the compiled kernels (``voxpose.voxels.surface_kernels``)."""

import numpy as np
import pytest

from tests.helpers import walk_motion
from voxpose import kernels
from voxpose.errors import VoxposeError
from voxpose.voxels import surface_kernels
from voxpose.voxels.cameras import circular_rig
from voxpose.voxels.surface import basis_indices, grid_sample, surface_mask
from voxpose.voxels.voxelize import voxelize_motion

needs_numba = pytest.mark.skipif(not kernels.numba_available(), reason="numba is not installed: numpy path only")


def kernel_sample(ijk, cell, offset=(0.0, 0.0, 0.0)):
    """The compiled kernel's grid sample, called as ``basis_indices`` calls it."""
    return surface_kernels.grid_sample(np.asarray(ijk, dtype=np.int64), float(cell), np.asarray(offset, dtype=float))


def cube(n, origin=(0, 0, 0)):
    return np.argwhere(np.ones((n, n, n), dtype=bool)) + np.array(origin)


def sphere(radius):
    r = int(np.ceil(radius))
    ijk = np.argwhere(np.ones((2 * r + 1,) * 3, dtype=bool)) - r
    return ijk[(ijk**2).sum(axis=1) <= radius**2]


def test_solid_cube_surface_is_its_shell():
    n = 7
    ijk = cube(n, origin=(-3, 10, 2))
    rng = np.random.default_rng(1)
    ijk = ijk[rng.permutation(len(ijk))]  # order must not matter
    mask = surface_mask(ijk)
    local = ijk - ijk.min(axis=0)
    shell = ((local == 0) | (local == n - 1)).any(axis=1)
    assert np.array_equal(mask, shell)
    assert mask.sum() == n**3 - (n - 2) ** 3


def test_surface_matches_brute_force_on_a_random_blob():
    rng = np.random.default_rng(0)
    ijk = np.unique(rng.integers(0, 8, size=(300, 3)), axis=0)
    occupied = set(map(tuple, ijk.tolist()))
    steps = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    expected = [any((i + a, j + b, k + c) not in occupied for a, b, c in steps) for i, j, k in ijk.tolist()]
    assert np.array_equal(surface_mask(ijk), expected)
    assert surface_mask(ijk).sum() < len(ijk)  # some voxels are interior


def test_thin_and_empty_shapes():
    plate = np.argwhere(np.ones((5, 1, 5), dtype=bool))
    assert surface_mask(plate).all()
    assert surface_mask(np.zeros((0, 3), dtype=np.int32)).shape == (0,)
    with pytest.raises(VoxposeError, match=r"shape \(N, 3\)"):
        surface_mask(np.zeros((4, 2), dtype=int))
    with pytest.raises(VoxposeError, match="integer voxel indices"):
        surface_mask(np.zeros((4, 3)))


def test_grid_sample_one_per_cell_nearest_the_centroid():
    # two clusters in two cells of side 4: the voxel nearest each cluster's centroid is picked
    ijk = np.array([[0, 0, 0], [1, 1, 1], [2, 2, 2], [5, 5, 5], [6, 6, 6], [6, 5, 5]])
    assert grid_sample(ijk, 4.0).tolist() == [1, 5]
    # shifted by 2, the cells are {0, 1}, {2, 3}, {4}, {5}; ties (equidistant pairs) go to the lower index
    assert grid_sample(ijk, 4.0, offset=(2.0, 2.0, 2.0)).tolist() == [0, 2, 4, 5]


@pytest.mark.parametrize("sample", [grid_sample, pytest.param(kernel_sample, marks=needs_numba)],
                         ids=["numpy", "numba"])  # fmt: skip
@pytest.mark.parametrize("cell, offset", [(3.0, (0.0, 0.0, 0.0)), (4.7, (1.3, 0.2, 3.9)), (1.0, (0.5, 0.5, 0.5))])
def test_grid_sample_matches_brute_force(cell, offset, sample):
    rng = np.random.default_rng(int(cell * 10))
    ijk = np.unique(rng.integers(-9, 25, size=(700, 3)), axis=0)[rng.permutation(600)]
    members = {}
    for n, voxel in enumerate(ijk.tolist()):
        members.setdefault(tuple(int(np.floor((x + o) / cell)) for x, o in zip(voxel, offset, strict=True)), []).append(
            n
        )
    expected = []
    for rows in members.values():
        centre = ijk[rows].mean(axis=0)
        dist = [float(((ijk[n] - centre) ** 2).sum()) for n in rows]
        expected.append(rows[int(np.argmin(dist))])  # argmin: the first (lowest) index among ties
    assert sample(ijk, cell, offset).tolist() == sorted(expected)
    if sample is kernel_sample:
        count = surface_kernels.count_cells(ijk, float(cell), np.asarray(offset, dtype=float))
        assert count == len(members)


@needs_numba
def test_the_kernels_pick_the_numpy_paths_basis_on_carved_hulls(monkeypatch):
    """Every frame of a carved walk, several seeds and counts (ties included: the cells' centroids fall on
    half-voxels): the same basis voxels, bit for bit."""
    seq = voxelize_motion(walk_motion(5), circular_rig(), progress_every=0)
    for f in range(seq.n_frames):
        ijk, surface, _ = seq.frame(f)
        for seed in (0, 1, 7):
            for n_basis in (200, 60, 13):
                out = {}
                for path in ("numba", "numpy"):
                    monkeypatch.setenv(kernels.ENV, path)
                    out[path] = basis_indices(ijk[surface], n_basis, seed)
                assert out["numba"].dtype == out["numpy"].dtype
                np.testing.assert_array_equal(out["numba"], out["numpy"])


def test_basis_count_coverage_and_determinism():
    surface = sphere(18.0)
    surface = surface[surface_mask(surface)]
    n = len(surface)
    basis = basis_indices(surface, n_basis=200, seed=5)
    assert 180 <= len(basis) <= 220  # "about 200"
    assert len(np.unique(basis)) == len(basis) and basis.min() >= 0 and basis.max() < n
    # coverage: every surface voxel is near a basis voxel; a uniform spread over the sphere's area
    # 4 pi r^2 gives cells of side about sqrt(4 pi r^2 / 200) = 4.5 voxels, diagonal 7.8
    dist = np.sqrt(((surface[:, None, :] - surface[basis][None, :, :]) ** 2).sum(-1)).min(axis=1)
    assert dist.max() <= 8.0 * np.sqrt(3)
    assert dist.mean() < 3.0
    # same seed, same basis; another seed, another basis of about the same size
    assert np.array_equal(basis, basis_indices(surface, n_basis=200, seed=5))
    other = basis_indices(surface, n_basis=200, seed=6)
    assert not np.array_equal(basis, other) and abs(len(other) - 200) <= 20


def test_small_sets_keep_every_voxel_and_bad_counts_fail():
    ijk = cube(3)
    assert basis_indices(ijk, n_basis=100).tolist() == list(range(27))
    assert basis_indices(np.zeros((0, 3), dtype=int)).shape == (0,)
    with pytest.raises(VoxposeError, match="n_basis must be a positive integer"):
        basis_indices(ijk, n_basis=0)
