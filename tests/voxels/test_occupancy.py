"""The voxels a body fills: the same set as testing every voxel centre of a box against every solid."""

import numpy as np

from tests.helpers import SPHERE, as_set, box_voxels, walk_motion
from voxpose.voxels.body import Ellipsoids, body_ellipsoids
from voxpose.voxels.occupancy import occupied_voxels


def brute_force(el: Ellipsoids, l_res, bounds) -> set:
    """Voxels of a box whose centres solve (x - c)^T Sigma^-1 (x - c) <= 1 for some solid (np.linalg.solve)."""
    ijk = box_voxels(bounds, l_res)
    x = (ijk + 0.5) * l_res
    inside = np.zeros(len(x), dtype=bool)
    for c, sigma in zip(el.centres, el.shape_matrices(), strict=True):
        d = x - c
        inside |= np.einsum("ni,ni->n", d, np.linalg.solve(sigma, d.T).T) <= 1.0
    return as_set(ijk[inside])


def test_a_walking_body_in_every_frame_matches_the_brute_force_set():
    motion = walk_motion(3, step=(0.31, 0.05, -0.23))
    el = body_ellipsoids(motion)
    l_res = 0.031
    frame, ijk = occupied_voxels(el, l_res)
    assert (np.diff(frame) >= 0).all() and set(frame.tolist()) == {0, 1, 2}
    for f in range(3):
        found = ijk[frame == f]
        lo, hi = motion.positions[f, 0] - 1.1, motion.positions[f, 0] + 1.1
        assert as_set(found) == brute_force(el.frame(f), l_res, (lo, hi))
        assert len(as_set(found)) == len(found)  # each voxel once although the solids overlap


def test_one_frame_without_a_frame_axis_and_a_sphere_by_its_volume():
    l_res = 0.01
    frame, ijk = occupied_voxels(SPHERE, l_res)
    assert (frame == 0).all()
    assert as_set(ijk) == brute_force(SPHERE, l_res, ([-0.4, 0.6, -0.4], [0.4, 1.4, 0.4]))
    assert abs(len(ijk) * l_res**3 / (4 / 3 * np.pi * 0.3**3) - 1) < 0.01  # the sphere's volume
