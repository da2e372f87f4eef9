"""Pictures of a prediction: an animated GIF of the carved voxels with the estimated (and true) skeleton.

Each frame shows the frame's surface voxels (grey), the estimated pose (red) and, where the true pose is
known, the true pose (black), both drawn on the model's output skeleton (``voxpose.motion.output_skeleton``) at the
hull centroid, as in the BVH: the picture compares joint angles, the quantity of Eq. 6, not body sizes
or positions. Gap frames (empty hull) show the word "gap" and no skeleton. The view is a fixed cube around
each frame's hull, as large as the largest hull of the sequence. Matplotlib's vertical axis shows the world's
Y. Frames are drawn with matplotlib and written by Pillow as one GIF (atomically).
"""

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

from voxpose.apply.predict import Prediction
from voxpose.errors import VoxposeError
from voxpose.evaluation.gallery import BONES
from voxpose.io.atomic import atomic_path
from voxpose.motion.pose_kinematics import forward_kinematics


def _skeletons(angles, valid, offsets, root):
    """(F, 14, 3) joint positions of ``angles`` at ``root``; NaN where not ``valid``."""
    out = np.full((len(angles), len(offsets), 3), np.nan)
    if valid.any():
        out[valid] = forward_kinematics(angles[valid], offsets)[0] + root[valid, None, :]
    return out


def _draw(ax, points, skeletons, centre, half, title):
    ax.cla()
    if len(points):
        ax.scatter(points[:, 0], points[:, 2], points[:, 1], s=1, c="0.65", alpha=0.35, depthshade=False)
    for skel, colour in skeletons:
        for j, p in BONES:
            seg = skel[[p, j]]
            ax.plot(seg[:, 0], seg[:, 2], seg[:, 1], color=colour, lw=2.0)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[2] - half, centre[2] + half)
    ax.set_zlim(centre[1] - half, centre[1] + half)
    ax.set_box_aspect((1, 1, 1), zoom=1.5)
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)


def render_gif(prediction: Prediction, offsets, path, *, every: int = 1, fps: float | None = None,
               size_px: int = 360) -> int:  # fmt: skip
    """Write the animation (module docstring) of every ``every``-th frame to ``path``; returns frames drawn."""
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        raise VoxposeError(f"render: --every must be a positive integer, got {every!r}")
    seq = prediction.voxels
    valid = prediction.valid
    est = _skeletons(prediction.angles, valid, offsets, prediction.root)
    truth = None
    if prediction.true_angles is not None:
        truth = _skeletons(prediction.true_angles, valid & np.isfinite(prediction.true_angles).all(axis=1),
                           offsets, prediction.root)  # fmt: skip
    extent = [np.ptp(seq.frame(f)[0], axis=0).max() for f in np.flatnonzero(~seq.empty)]
    half = 0.55 * (max(extent) + 1) * seq.l_res
    last_centre = np.nanmean(prediction.root, axis=0)
    dpi = 100
    fig = Figure(figsize=(size_px / dpi, size_px / dpi), dpi=dpi)
    canvas = FigureCanvasAgg(fig)  # draws into a pixel buffer; no pyplot, no backend switch
    fig.subplots_adjust(left=0, right=1, bottom=0, top=0.93)
    ax = fig.add_subplot(projection="3d")
    images = []
    for f in range(0, seq.n_frames, every):
        ijk, surface, _ = seq.frame(f)
        points = (ijk[surface] + 0.5) * seq.l_res
        if valid[f]:
            last_centre = prediction.root[f]
            skeletons = [(est[f], "r")] + ([] if truth is None else [(truth[f], "k")])
            title = f"frame {prediction.frames[f]}"
            if truth is not None:
                diff = np.mod(prediction.true_angles[f] - prediction.angles[f], 360.0)
                title += f": {np.minimum(diff, 360.0 - diff).mean():.1f} deg"
        else:
            skeletons, title = [], f"frame {prediction.frames[f]}: gap (empty hull)"
        _draw(ax, points, skeletons, last_centre, half, title)
        canvas.draw()
        rgba = np.asarray(canvas.buffer_rgba())
        images.append(Image.fromarray(rgba[..., :3]).convert("P", palette=Image.Palette.ADAPTIVE))
    duration = int(round(1000.0 * every / (fps or prediction.fps)))
    with atomic_path(path) as tmp:
        images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:], duration=duration, loop=0)
    return len(images)
