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


KIND_WORDS = {
    "walk": "regular walking",
    "drunk": "drunken walking",
    "spiral": "spiral walking",
    "jog": "jogging",
    "jump": "jumping",
}


def gallery(predictions: dict, voxels: dict, per_kind: int = 3, method: str = "mvrvm"):
    """Figure of ``per_kind`` frames per motion type, one column per type; ``voxels``: motion -> (VoxelSequence,
    meta). Each panel names the type, the motion, the frame and its Eq. 6 error; its box fits the body, so the
    figure is not mostly white space."""
    picks = [p for p in pick_frames(predictions, per_kind) if p[0] in voxels]
    kinds = list(dict.fromkeys(kind_of(name) for name, _ in picks))
    n_cols = max(1, len(kinds))
    n_rows = max(1, max((sum(kind_of(n) == k for n, _ in picks) for k in kinds), default=1))
    fig = Figure(figsize=(2.5 * n_cols, 3.9 * n_rows))
    row_of = {}
    for name, f in picks:
        kind = kind_of(name)
        row = row_of[kind] = row_of.get(kind, -1) + 1
        seq, _ = voxels[name]
        pred = predictions[name]
        ijk, surface, _ = seq.frame(f)
        points = (ijk[surface] + 0.5) * seq.l_res
        root = pred["root_positions"][f] + seq.shifts[f]
        true = _skeleton(pred["true"][f], pred["offsets"], root)
        est = _skeleton(pred[f"pred_{method}"][f], pred["offsets"], root)
        ax = fig.add_subplot(n_rows, n_cols, row * n_cols + kinds.index(kind) + 1, projection="3d")
        ax.scatter(points[:, 0], points[:, 2], points[:, 1], s=1, c="0.65", alpha=0.35, depthshade=False)
        for skel, colour in ((true, "k"), (est, "r")):
            for j, p in BONES:
                seg = skel[[p, j]]
                ax.plot(seg[:, 0], seg[:, 2], seg[:, 1], color=colour, lw=1.8)
        every = np.concatenate([points, true, est])
        low, high = every.min(axis=0) - 0.02, every.max(axis=0) + 0.02
        ax.set_xlim(low[0], high[0])
        ax.set_ylim(low[2], high[2])
        ax.set_zlim(low[1], high[1])
        ax.set_box_aspect((high - low)[[0, 2, 1]], zoom=1.25)
        ax.set_axis_off()
        ax.set_title(
            f"{KIND_WORDS.get(kind, kind)}\n{name}, frame {f}\nerror {pred[f'frame_error_{method}'][f]:.1f} deg",
            fontsize=11,
        )
    fig.suptitle("Test frames: carved voxels (grey), true skeleton (black), estimate (red)", fontsize=13)
    fig.subplots_adjust(left=0, right=1, bottom=0, top=1 - 0.8 / fig.get_figheight(), wspace=0.02, hspace=0.12)
    return fig
