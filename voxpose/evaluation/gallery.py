"""A Figure 5-style gallery: a test frame's carved voxels with the estimated skeleton over the true one.

Skeletons are forward kinematics of y' (``voxpose.motion.pose_kinematics``) on the subject's own offsets,
placed at the true
root position in the voxel frame (the regressor estimates pose, not position; ``shifts`` re-centred the body
before rendering). Matplotlib's vertical axis shows the world's Y.
"""

import numpy as np
from matplotlib.figure import Figure

from voxpose.motion import canon
from voxpose.motion.data import kind_of
from voxpose.motion.pose_kinematics import forward_kinematics

BONES = [(j, p) for j, p in enumerate(canon.PARENTS) if p >= 0]


def pick_frames(predictions: dict, per_kind: int) -> list:
    """(motion, frame) pairs: ``per_kind`` valid frames per motion type, evenly spread over its motions."""
    by_kind = {}
    for name in sorted(predictions):
        kind = kind_of(name)
        frames = np.flatnonzero(predictions[name]["valid"])
        by_kind.setdefault(kind, []).extend((name, int(f)) for f in frames)
    picks = []
    for kind in sorted(by_kind):
        items = by_kind[kind]
        idx = np.linspace(0, len(items) - 1, per_kind + 2)[1:-1].round().astype(int)
        picks.extend(items[i] for i in sorted(set(idx)))
    return picks


def _skeleton(angles, offsets, root):
    positions, _ = forward_kinematics(angles[None], offsets)
    return positions[0] + root


def gallery(predictions: dict, voxels: dict, per_kind: int = 3, method: str = "mvrvm"):
    """Figure of ``per_kind`` frames per motion type; ``voxels``: motion -> (VoxelSequence, meta)."""
    picks = [p for p in pick_frames(predictions, per_kind) if p[0] in voxels]
    n_cols = min(6, max(1, len(picks)))
    n_rows = int(np.ceil(len(picks) / n_cols))
    fig = Figure(figsize=(3.4 * n_cols, 4.2 * n_rows))
    for i, (name, f) in enumerate(picks):
        seq, _ = voxels[name]
        pred = predictions[name]
        ijk, surface, _ = seq.frame(f)
        points = (ijk[surface] + 0.5) * seq.l_res
        root = pred["root_positions"][f] + seq.shifts[f]
        true = _skeleton(pred["true"][f], pred["offsets"], root)
        est = _skeleton(pred[f"pred_{method}"][f], pred["offsets"], root)
        ax = fig.add_subplot(n_rows, n_cols, i + 1, projection="3d")
        ax.scatter(points[:, 0], points[:, 2], points[:, 1], s=1, c="0.7", alpha=0.35, depthshade=False)
        for skel, colour in ((true, "k"), (est, "r")):
            for j, p in BONES:
                seg = skel[[p, j]]
                ax.plot(seg[:, 0], seg[:, 2], seg[:, 1], color=colour, lw=1.6)
        centre = points.mean(axis=0)
        half = 0.5 * max(np.ptp(points, axis=0).max(), 1e-3)
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[2] - half, centre[2] + half)
        ax.set_zlim(centre[1] - half, centre[1] + half)
        ax.set_axis_off()
        ax.set_title(f"{name}\nframe {f}: {pred[f'frame_error_{method}'][f]:.1f} deg", fontsize=7)
    fig.suptitle("voxels (grey), true skeleton (black), estimate (red)", fontsize=9)
    fig.tight_layout()
    return fig
