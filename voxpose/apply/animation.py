"""Pictures of a prediction as a camera sees it: surface voxels with the estimated (and true) skeleton.

View. Every frame is drawn through a calibrated camera (``voxpose.voxels.cameras``, lens distortion included):
a camera of the recording's rig, so that the picture lies on that camera's image (``images``, e.g. the
recording's frames), or a virtual one orbiting the subject (``orbit_camera``: ``azimuth`` degrees around the
vertical from +Z towards +X, as ``circular_rig`` numbers its cameras, and ``elevation`` degrees above the
horizontal). A camera projection is a true picture of the right-handed world: nothing is mirrored, so a
subject's left hand appears where a photograph would show it (``tests/apply/test_render.py``).

Skeleton placement. The regressor estimates joint angles only (Section 2). The skeleton of the estimated (red)
and, when known, true (black) pose is drawn on the model's output skeleton with its root where the body
model in that pose best overlaps the frame's hull (``voxpose.apply.root_fit``, as ``voxpose predict`` places the
BVH root), so a long dress or raised arms, which move the hull's centroid, do not move the skeleton. Surface
voxels are grey dots; gap frames (empty hull) show the word "gap".

Output: one PNG per frame (a path holding ``{frame}``, the input's frame number), an animated GIF (``.gif``,
Pillow) or an MP4 (``.mp4``, the optional extra ``voxpose[video]``), each written atomically.
"""

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

from voxpose.apply.predict import Prediction
from voxpose.apply.root_fit import fit_roots
from voxpose.errors import VoxposeError
from voxpose.evaluation.gallery import BONES
from voxpose.io.atomic import atomic_path
from voxpose.motion import canon
from voxpose.motion.output_skeleton import OutputSkeleton
from voxpose.motion.pose_kinematics import forward_kinematics
from voxpose.voxels.cameras import Camera, look_at

VIEW_PX = 360


def placed_skeletons(angles, valid, skeleton: OutputSkeleton, seq) -> np.ndarray:
    """(F, 14, 3) joints of ``angles`` placed on each frame's hull (module docstring); NaN where not ``valid``."""
    out = np.full((len(angles), canon.N_JOINTS, 3), np.nan)
    if not valid.any():
        return out
    roots = fit_roots(seq, angles, valid, skeleton, name="render")
    out[valid] = forward_kinematics(angles[valid], skeleton.offsets)[0] + roots[valid, None]
    return out


def orbit_camera(centre, extent: float, azimuth: float, elevation: float, size_px: int = VIEW_PX) -> Camera:
    """A virtual camera looking at ``centre`` from ``azimuth``/``elevation`` degrees (module docstring), far
    enough (three times ``extent`` metres) for a cube of side ``extent`` to fill about half of its image."""
    if not -89.0 <= elevation <= 89.0:
        raise VoxposeError(f"render: --elevation must lie in [-89, 89] degrees, got {elevation}")
    az, el = np.radians(azimuth), np.radians(elevation)
    distance = 3.0 * extent
    eye = np.asarray(centre) + distance * np.array([np.cos(el) * np.sin(az), np.sin(el), np.cos(el) * np.cos(az)])
    rot, t = look_at(eye, centre)
    focal = 0.5 * size_px * distance / extent
    k = [[focal, 0.0, (size_px - 1) / 2], [0.0, focal, (size_px - 1) / 2], [0.0, 0.0, 1.0]]
    return Camera("view", k, rot, t, size_px, size_px)


def _projected(camera: Camera, points):
    """Pixel coordinates (N, 2) of points in front of the camera, NaN for the others."""
    uv, depth = camera.project(points, return_depth=True)
    return np.where((depth > 0)[..., None], uv, np.nan)


def draw_frames(prediction: Prediction, skeleton: OutputSkeleton, camera: Camera, *, every: int = 1, images=None):
    """Yield (frame number, (H, W, 3) uint8 picture) of every ``every``-th frame (module docstring).

    ``images``: a function of the frame number returning the camera's (H, W, 3) image, or None (white).
    """
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        raise VoxposeError(f"render: --every must be a positive integer, got {every!r}")
    seq, valid = prediction.voxels, prediction.valid
    est = placed_skeletons(prediction.angles, valid, skeleton, seq)
    truth = None
    if prediction.true_angles is not None:
        known = valid & np.isfinite(prediction.true_angles).all(axis=1)
        truth = placed_skeletons(prediction.true_angles, known, skeleton, seq)
    dpi = 100
    fig = Figure(figsize=(camera.width / dpi, camera.height / dpi), dpi=dpi)
    canvas = FigureCanvasAgg(fig)  # draws into a pixel buffer; no pyplot, no backend switch
    ax = fig.add_axes((0, 0, 1, 1))
    for f in range(0, seq.n_frames, every):
        number = prediction.frames[f]
        ax.cla()
        ax.set_xlim(-0.5, camera.width - 0.5)
        ax.set_ylim(camera.height - 0.5, -0.5)  # image rows go down
        ax.set_axis_off()
        if images is not None:
            ax.imshow(images(number), extent=(-0.5, camera.width - 0.5, camera.height - 0.5, -0.5))
        ijk, surface, _ = seq.frame(f)
        if len(ijk):
            dots = _projected(camera, (ijk[surface] + 0.5) * seq.l_res)
            ax.scatter(dots[:, 0], dots[:, 1], s=2, c="0.55", alpha=0.5, linewidths=0)
        title = f"frame {number}"
        if valid[f]:
            for skel, colour in [(est[f], "r")] + ([] if truth is None else [(truth[f], "k")]):
                joints = _projected(camera, skel)
                for j, p in BONES:
                    ax.plot(joints[[p, j], 0], joints[[p, j], 1], color=colour, lw=2.0)
            if truth is not None:
                diff = np.mod(prediction.true_angles[f] - prediction.angles[f], 360.0)
                title += f": {np.minimum(diff, 360.0 - diff).mean():.1f} deg"
        else:
            title += ": gap (empty hull)"
        ax.text(0.02, 0.98, title, transform=ax.transAxes, va="top", fontsize=9,
                bbox={"facecolor": "white", "alpha": 0.6, "linewidth": 0})  # fmt: skip
        canvas.draw()
        yield number, np.asarray(canvas.buffer_rgba())[..., :3].copy()


def write_pictures(frames, path, fps: float) -> int:
    """Write (frame number, picture) pairs as PNGs (``{frame}`` in ``path``), a GIF or an MP4; returns their count."""
    path = str(path)
    if "{frame}" in path:
        count = 0
        for number, picture in frames:
            with atomic_path(path.replace("{frame}", f"{number:06d}")) as tmp:
                Image.fromarray(picture).save(tmp, format="PNG")
            count += 1
        return count
    pictures = [picture for _, picture in frames]
    if path.lower().endswith(".gif"):
        images = [Image.fromarray(p).convert("P", palette=Image.Palette.ADAPTIVE) for p in pictures]
        with atomic_path(path) as tmp:
            images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:],
                           duration=int(round(1000.0 / fps)), loop=0)  # fmt: skip
        return len(images)
    try:
        import imageio.v3 as iio
    except ImportError:
        raise VoxposeError(f"-o {path}: writing MP4 needs the optional extra: pip install 'voxpose[video]'") from None
    with atomic_path(path) as tmp:
        named = tmp.with_name(tmp.name + ".mp4")  # ffmpeg chooses the container by the file's suffix
        try:
            iio.imwrite(named, np.stack(pictures), fps=fps)
            named.replace(tmp)
        finally:
            named.unlink(missing_ok=True)
    return len(pictures)
