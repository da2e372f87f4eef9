"""The compiled carving kernels (``voxpose.voxels.carve_kernels``) give the numpy path's voxels exactly, with and
without lens distortion, damaged and empty views; ``VOXPOSE_KERNELS`` selects the path. Skipped without numba."""

import numpy as np
import pytest

from tests.helpers import tpose, walk_motion
from tests.voxels.test_lens import WIDE, distorted
from voxpose import kernels
from voxpose.voxels import carve
from voxpose.voxels.body import body_ellipsoids
from voxpose.voxels.cameras import circular_rig
from voxpose.voxels.carve import Carver
from voxpose.voxels.render import render_silhouettes

pytestmark = pytest.mark.skipif(not kernels.numba_available(), reason="numba is not installed: numpy path only")


def both(carver, sil):
    """(numba voxels, numpy voxels) of one frame."""
    out = []
    for kind in ("numba", "numpy"):
        with pytest.MonkeyPatch.context() as mp:
            mp.setenv(kernels.ENV, kind)
            out.append(carver(sil))
    return out


@pytest.mark.parametrize("min_views", [6, 5, 4])
def test_kernels_carve_the_numpy_paths_voxels(min_views):
    rig = circular_rig()
    motion = walk_motion(3)
    el = body_ellipsoids(motion).translated(-motion.positions[:, 0] * [1, 0, 1])
    carver = Carver(rig, 1.75 / 60, min_views=min_views)
    rng = np.random.default_rng(min_views)
    for f in range(motion.n_frames):
        sil = render_silhouettes(el.frame(f), rig)
        sil[f % 6, : 150 + 30 * f] = False  # a damaged view
        sil ^= rng.random(sil.shape) < 0.002  # salt and pepper: windows neither empty nor full
        fast, slow = both(carver, sil)
        assert len(slow) > 500
        np.testing.assert_array_equal(fast, slow)


def test_kernels_on_a_distorted_rig_and_empty_views():
    bent = distorted(circular_rig(**WIDE))
    sil = render_silhouettes(body_ellipsoids(tpose(root_xz=(0.3, -0.2))).frame(0), bent)
    carver = Carver(bent, 0.05, bounds=[[-1.2, -0.2, -1.2], [1.2, 2.2, 1.2]])
    fast, slow = both(carver, sil)
    assert len(slow) > 100
    np.testing.assert_array_equal(fast, slow)
    sil[1] = False  # one empty view: no hull with every view, a hull with the others
    for carver in (Carver(bent, 0.05, min_views=4), Carver(bent, 0.05, min_views=3)):
        fast, slow = both(carver, sil)
        np.testing.assert_array_equal(fast, slow)
    assert len(fast) > 100


def test_summed_area_tables_are_equal():
    rng = np.random.default_rng(0)
    sil = rng.random((4, 40, 30)) < 0.3
    sil[2] = False
    sil[3, :5] = sil[3, -7:] = False
    tables = []
    for kind in ("numba", "numpy"):
        with pytest.MonkeyPatch.context() as mp:
            mp.setenv(kernels.ENV, kind)
            tables.append(carve._summed_areas(sil))
    for a, b in zip(*tables, strict=True):
        np.testing.assert_array_equal(a, b)
    assert tables[0][0].dtype == tables[1][0].dtype == np.int32
