"""Compiled (numba) kernel of the root fit's hill climb (:mod:`voxpose.apply.root_fit`, step 2), selected by
:mod:`voxpose.kernels`.

The same climb as the numpy path: every frame still climbing counts, for each of the seven shifts (stay, then
-x, +x, -y, +y, -z, +z), the body voxels falling on hull voxels, and moves to the first best one. The counts are
integers, so shifts and scores are the numpy path's exactly (``tests/apply/test_root_fit.py``); the loop skips
the numpy path's per-step temporaries (index arrays over every body voxel, seven ``np.bincount`` calls).
"""

import numpy as np

from voxpose.kernels import jit


@jit
def climb(occupied, shape, offsets, steps, body_frame, body, shift, lo, scores, max_climb):  # pragma: no cover
    """Climb ``shift`` (n, 3) in place, leaving the last counts in ``scores`` (n, 7); returns the number of frames
    still climbing after ``max_climb`` steps. ``occupied`` is the flat (n, *shape) hull grid of voxels
    ``ijk - lo[frame]``, ``offsets`` the steps as flat-index offsets."""
    n = shift.shape[0]
    active = np.ones(n, dtype=np.bool_)
    n_active = n
    for _ in range(max_climb):
        for f in range(n):
            if active[f]:
                scores[f, :] = 0.0
        for i in range(body.shape[0]):
            f = body_frame[i]
            if not active[f]:
                continue
            x = body[i, 0] + shift[f, 0] - lo[f, 0]
            y = body[i, 1] + shift[f, 1] - lo[f, 1]
            z = body[i, 2] + shift[f, 2] - lo[f, 2]
            if x < 1 or y < 1 or z < 1 or x > shape[0] - 2 or y > shape[1] - 2 or z > shape[2] - 2:
                continue  # one step from the grid's edge: misses the hull at every step
            flat = ((f * shape[0] + x) * shape[1] + y) * shape[2] + z
            for s in range(offsets.shape[0]):
                scores[f, s] += occupied[flat + offsets[s]]
        n_active = 0
        for f in range(n):
            if active[f]:
                best = np.argmax(scores[f])  # the first maximum: the current shift on a tie
                if best > 0:
                    shift[f] += steps[best]
                    n_active += 1
                else:
                    active[f] = False
        if n_active == 0:
            break
    return n_active
