"""Training-frame thinning of an experiment's regression (voxpose.regression_run.thin_frames)."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.regression_run import thin_frames


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
