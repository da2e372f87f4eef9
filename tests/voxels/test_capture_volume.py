"""The bounding box of an intersection of half-spaces (``voxels.capture_volume``), against known boxes and
``scipy.optimize.linprog``; empty and unbounded regions have none."""

import itertools

import numpy as np
import pytest
from scipy.optimize import linprog

from voxpose.voxels.capture_volume import polytope_box


def _cube(lo, hi):
    """Half-spaces ``n @ x <= b`` of the box lo..hi."""
    normals = np.concatenate([np.eye(3), -np.eye(3)])
    return normals, np.concatenate([np.asarray(hi, float), -np.asarray(lo, float)])


def test_a_box_with_redundant_and_corner_planes_is_itself():
    normals, offsets = _cube([-1.0, 0.5, 2.0], [3.0, 1.5, 2.25])
    # a redundant plane far away, and one through a corner (four planes meet there)
    normals = np.concatenate([normals, [[1.0, 1.0, 1.0], [1.0, 1.0, 0.0]]])
    offsets = np.concatenate([offsets, [100.0, 4.5]])
    np.testing.assert_allclose(polytope_box(normals, offsets), [[-1.0, 0.5, 2.0], [3.0, 1.5, 2.25]], atol=1e-12)


def test_a_cut_corner_shrinks_the_box_where_the_plane_says():
    normals, offsets = _cube([0.0, 0.0, 0.0], [1.0, 1.0, 1.0])
    normals = np.concatenate([normals, [[1.0, 1.0, 0.0]]])  # x + y <= 0.5: x and y each reach 0.5 at most
    offsets = np.concatenate([offsets, [0.5]])
    np.testing.assert_allclose(polytope_box(normals, offsets), [[0.0, 0.0, 0.0], [0.5, 0.5, 1.0]], atol=1e-12)


@pytest.mark.parametrize("seed", range(6))
def test_random_polytopes_have_linprogs_box(seed):
    """Tangent planes of an ellipsoid at random points (a bounded polytope around it), shifted: each face of the
    box equals the linear program's optimum in that direction."""
    rng = np.random.default_rng(seed)
    directions = rng.normal(size=(8 + 4 * seed, 3))
    normals = directions / np.linalg.norm(directions, axis=1)[:, None] * rng.uniform(0.5, 2.0, (len(directions), 1))
    normals = np.concatenate([normals, np.concatenate([np.eye(3), -np.eye(3)])])  # always bounded
    centre = rng.normal(size=3)
    offsets = normals @ centre + rng.uniform(0.5, 3.0, len(normals))
    box = polytope_box(normals, offsets)
    for axis, sign in itertools.product(range(3), (1.0, -1.0)):
        cost = np.zeros(3)
        cost[axis] = sign
        best = linprog(cost, A_ub=normals, b_ub=offsets, bounds=[(None, None)] * 3, method="highs")
        assert best.status == 0
        assert box[0 if sign > 0 else 1, axis] == pytest.approx(best.x[axis], abs=1e-7)


def test_unbounded_and_empty_regions_have_no_box():
    cone = np.array([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [1.0, 1.0, -1.0], [0.0, 0.0, -1.0]])  # widens towards +z
    assert polytope_box(cone, np.ones(4)) is None
    slab = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0]])  # a square prism
    assert polytope_box(slab, np.ones(4)) is None
    normals, offsets = _cube([0.0, 0.0, 0.0], [1.0, 1.0, 1.0])
    assert polytope_box(normals, offsets - np.array([0, 0, 0, 2.0, 0, 0])) is None  # x <= 1 and x >= 2: empty
    closed = np.concatenate([cone, [[0.0, 0.0, 1.0]]])  # the cone with a lid
    np.testing.assert_allclose(polytope_box(closed, np.ones(5))[1, 2], 1.0)
