"""Training-frame thinning of an experiment's regression (voxpose.evaluation.run.thin_frames)."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.evaluation.run import thin_frames


def test_no_thinning_when_the_frames_fit():
    valid = [np.ones(30, bool), np.ones(20, bool)]
    assert thin_frames(valid, None) is valid
    assert thin_frames(valid, 50) is valid


def test_smallest_even_stride_that_fits_keeps_every_motion():
    valid = [np.ones(100, bool), np.ones(41, bool)]
    valid[0][[3, 4]] = False  # gaps are skipped, not counted
    kept = thin_frames(valid, 50)
    # brute force: stride 2 leaves 49 + 21 = 70 > 50, stride 3 leaves 33 + 14 = 47 <= 50
    assert [int(k.sum()) for k in kept] == [33, 14]
    assert np.array_equal(np.flatnonzero(kept[1]), np.arange(0, 41, 3))
    assert not (kept[0] & ~valid[0]).any()
    assert np.diff(np.flatnonzero(kept[0])[:3]).tolist() == [5, 3]  # 0, then 5 (3 and 4 are gaps), then 8


def test_cap_below_the_number_of_motions_is_refused():
    with pytest.raises(VoxposeError, match="max_train_frames"):
        thin_frames([np.ones(5, bool)] * 12, 10)


@pytest.mark.filterwarnings("ignore::voxpose.errors.ConvergenceWarning")  # the budgets are that small on purpose
def test_width_selection_fits_get_their_own_budget(tmp_path):
    """The candidate fits stop at ``selection_max_iter`` moves; the final fit keeps ``max_iter``."""
    from voxpose.evaluation.run import run
    from voxpose.io.bvh import write_bvh
    from voxpose.motion.generate import generate_motion
    from voxpose.motion.load import load_motion

    motions, features = {}, {}
    rng = np.random.default_rng(0)
    for i, kind in enumerate(("walk", "jog", "walk")):
        path = tmp_path / f"{kind}_gen_{i:02d}.bvh"
        write_bvh(generate_motion(kind, seed=i, n_frames=40, height=1.75), path)
        motion = load_motion(path)
        motions[motion.name] = motion
        angles = np.radians(motion.angles)
        planted = np.hstack([np.sin(angles), np.cos(angles)]) + 0.01 * rng.standard_normal((40, 84))
        features[motion.name] = {"features": planted, "counts": np.full(40, 200)}
    names = sorted(motions)
    cfg = {"pca_variance": 0.9, "heading": "vector", "kernel_width": "auto", "width_scales": [0.8, 1.0],
           "max_iter": 40, "selection_max_iter": 3, "tol": 1e-3}  # fmt: skip
    summary = run(features, motions, names[:2], names[2:], cfg, seed=0).summary
    assert [row["n_iter"] for row in summary["width_selection"]] == [3, 3]
    assert summary["mvrvm"]["n_iter"] > 3
    cfg["selection_max_iter"] = None  # null: the candidates get max_iter too
    summary = run(features, motions, names[:2], names[2:], cfg, seed=0).summary
    assert all(row["n_iter"] > 3 for row in summary["width_selection"])
