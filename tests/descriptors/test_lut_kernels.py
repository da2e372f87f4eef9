"""The compiled 3D shape context kernel (``voxpose.descriptors.lut_kernels``, soft votes) equals the reference and
the numpy path to 1e-12; ``VOXPOSE_KERNELS`` selects the path. Skipped where numba is not installed."""

import numpy as np
import pytest

from tests.descriptors.test_lut import BOUNDARY_OFFSETS, PARAMS, blob, reference
from tests.helpers import walk_motion
from voxpose import kernels
from voxpose.descriptors import lut_kernels
from voxpose.descriptors.lut import ShapeContextTable
from voxpose.errors import VoxposeError
from voxpose.voxels.cameras import circular_rig
from voxpose.voxels.voxelize import voxelize_motion

pytestmark = pytest.mark.skipif(not kernels.numba_available(), reason="numba is not installed: numpy path only")


def describe(kind, surface, basis, h_sub_voxels=60.0, **params):
    """The fast path with the kernels of ``kind`` ("numba" or "numpy")."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv(kernels.ENV, kind)
        return ShapeContextTable(h_sub_voxels, **params).describe(surface, basis)


@pytest.mark.parametrize("params", [*PARAMS, {"n_a": 9}, {"n_a": 7, "n_e": 4}],
                         ids=lambda p: ",".join(f"{k}={v}" for k, v in p.items()) or "paper")  # fmt: skip
def test_kernel_equals_reference_and_numpy_path(params):
    params = dict(params)
    h_sub_voxels = params.pop("h_sub_voxels", 60.0)
    surface, basis = blob(sum(map(ord, str(params))))
    fast = describe("numba", surface, basis, h_sub_voxels, soft=True, **params)
    np.testing.assert_allclose(fast, reference(surface, basis, h_sub_voxels, soft=True, **params), rtol=0, atol=1e-12)
    np.testing.assert_allclose(fast, describe("numpy", surface, basis, h_sub_voxels, soft=True, **params),
                               rtol=0, atol=1e-12)  # fmt: skip


def test_odd_azimuth_count_keeps_both_signs_of_x():
    geometry = ShapeContextTable(60, n_a=9, soft=True).geometry
    assert not lut_kernels.folded_table(geometry).fold_x
    assert lut_kernels.folded_table(ShapeContextTable(60, soft=True).geometry).fold_x


def test_boundary_offsets_far_voxels_and_duplicates():
    basis = np.array([[30, 40, 20]])
    surface = basis + BOUNDARY_OFFSETS
    np.testing.assert_allclose(describe("numba", surface, basis, soft=True), reference(surface, basis, soft=True),
                               rtol=0, atol=1e-12)  # fmt: skip
    outside = basis + [(20, 0, 0), (12, 16, 0), (0, -12, 16), (0, 0, 0), (1, 1, 0)]
    assert not describe("numba", outside, basis, soft=True).any()
    surface, basis = blob(11)
    far = np.array([[200, 0, 0], [0, 150, 0], [0, 0, 120], [-90, 5, 7], [3, -130, 2], [41, 41, 41]])
    surface = np.vstack([surface, far, far + [2, 3, 1], surface[:30]])  # far voxels and repeated ones
    basis = np.vstack([basis, far[:2]])
    np.testing.assert_allclose(describe("numba", surface, basis, soft=True), reference(surface, basis, soft=True),
                               rtol=0, atol=1e-12)  # fmt: skip


def test_kernel_on_a_carved_walking_figure_equals_the_numpy_path():
    seq = voxelize_motion(walk_motion(2), circular_rig(), progress_every=0)
    h_sub_voxels = seq.h_sub / seq.l_res
    for f in range(seq.n_frames):
        ijk, surface, basis = seq.frame(f)
        fast = describe("numba", ijk[surface], ijk[basis], h_sub_voxels, soft=True)
        assert (fast > 0).sum() > 50 * len(basis)
        np.testing.assert_allclose(fast, describe("numpy", ijk[surface], ijk[basis], h_sub_voxels, soft=True),
                                   rtol=0, atol=1e-12)  # fmt: skip


def test_kernel_does_not_depend_on_surface_order_and_normalises():
    surface, basis = blob(21, n_surface=1500, n_basis=60)
    base = describe("numba", surface, basis, soft=True)
    shuffled = surface[np.random.default_rng(0).permutation(len(surface))]
    np.testing.assert_array_equal(describe("numba", shuffled, basis, soft=True), base)
    normalised = describe("numba", surface, basis, soft=True, normalise=True)
    np.testing.assert_allclose(normalised, base / base.sum(axis=1, keepdims=True), rtol=1e-12, atol=0)


def test_switch_selects_the_path(monkeypatch):
    surface, basis = blob(3)
    calls = []
    original = lut_kernels.soft_votes
    monkeypatch.setattr(lut_kernels, "soft_votes", lambda *a: calls.append(1) or original(*a))
    describe("numpy", surface, basis, soft=True)
    describe("numba", surface, basis, soft=False)  # hard votes: the numpy path, which the kernel did not beat
    assert calls == []
    describe("numba", surface, basis, soft=True)
    assert calls == [1]
    monkeypatch.setenv(kernels.ENV, "fortran")
    with pytest.raises(VoxposeError, match="VOXPOSE_KERNELS='fortran'"):
        kernels.use_numba()


def test_an_empty_support_fails_at_construction_on_both_paths(monkeypatch):
    for kind in ("numba", "numpy"):
        monkeypatch.setenv(kernels.ENV, kind)
        with pytest.raises(VoxposeError, match="no voxel offset lies in the support"):
            ShapeContextTable(60, r_min=2.5, r_max=2.55 / 60, soft=True)
