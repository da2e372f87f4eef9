"""A generated studio as a lab would bring it (issue 19, README "Your own studio"): an OpenCV calibration in
millimetres with Z up and lens distortion, images of the empty scene and of a moving body with sensor noise,
a lighting change and a shadow.

``python -m tests.studio DIR [--rig RIG.json] [--motion MOTION.h5]`` writes into DIR:

* ``calib/cam<i>.yaml``: OpenCV FileStorage YAML per camera (``camera_matrix``, ``distortion_coefficients``,
  ``rvec``, ``tvec`` in mm, ``image_width``/``image_height``), the world on the floor with Z up;
* ``background/cam<i>/<n>.png``: 5 noisy images of the empty scene;
* ``frames/cam<i>/<frame>.png``: the body of the motion (default: a generated walk) in each camera, frame
  numbers starting at 100, 10% dimmer light than the background and a shadow on the floor at the feet;
* ``truth/``: the exact rig (``rig.json``, Y up, metres, with distortion) and exact silhouettes.

The cameras are those of ``--rig`` (default: 6 on a circle, 128 x 128) with a barrel distortion; the body is
placed as ``voxelize_motion`` places it (root above the rig's centre), so the workflow's own voxels of the
motion (pinhole rig, exact silhouettes) are the reference the studio's carving is compared with.
"""

import argparse
import json
from pathlib import Path

import numpy as np
from PIL import Image

from voxpose.voxels.cameras import Camera, Rig, circular_rig, load_rig, save_rig
from voxpose.voxels.degrade import posed_body
from voxpose.voxels.render import render_silhouettes

DIST = [-1.5, 1.2, 0.002, -0.003, 0.0]  # a wide-angle lens: moves the body by about a voxel (h/30 at 4 m)
Z_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])  # studio (Z up) -> voxpose world (Y up)
FIRST_FRAME = 100
NOISE = 3.0  # grey levels (8-bit) of Gaussian sensor noise
LIGHT = 0.9  # the recording's light relative to the background's
SHADOW = 0.55  # brightness of the floor in the subject's shadow


def distorted(rig: Rig, dist=DIST) -> Rig:
    return Rig(rig.name, [Camera(c.name, c.K, c.R, c.t, c.width, c.height, dist) for c in rig])


def _matrix(name, array):
    array = np.atleast_2d(np.asarray(array, dtype=float))
    data = ", ".join(f"{v:.17g}" for v in array.reshape(-1))
    rows, cols = array.shape
    return f"{name}: !!opencv-matrix\n   rows: {rows}\n   cols: {cols}\n   dt: d\n   data: [ {data} ]\n"


def opencv_yaml(cam: Camera) -> str:
    """One camera as OpenCV FileStorage YAML, in the studio's world (mm, Z up): X = Z_UP X_studio / 1000."""
    rot = cam.R @ Z_UP  # camera of studio points: R X = R Z_UP X_studio / 1000
    rvec = _rotvec(rot)
    return ("%YAML:1.0\n---\n" + f"image_width: {cam.width}\nimage_height: {cam.height}\n"
            + _matrix("camera_matrix", cam.K) + _matrix("distortion_coefficients", [cam.dist])
            + _matrix("rvec", rvec[:, None]) + _matrix("tvec", 1000.0 * cam.t[:, None]))  # fmt: skip


def _rotvec(rot):
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(rot).as_rotvec()


def _background(rig: Rig, rng) -> np.ndarray:
    """(C, H, W, 3) smooth, mostly grey backgrounds (a studio's walls and floor), 50-210 grey levels."""
    from scipy.ndimage import gaussian_filter

    height, width = rig.image_size
    smooth = gaussian_filter(rng.uniform(size=(len(rig), height, width, 4)), sigma=(0, 6, 6, 0))
    smooth = (smooth - smooth.min(axis=(1, 2, 3), keepdims=True)) / np.ptp(smooth, axis=(1, 2, 3), keepdims=True)
    return 60.0 + 130.0 * smooth[..., :1] + 20.0 * smooth[..., 1:]


def _shadow(rig: Rig, body) -> np.ndarray:
    """(C, H, W) bool: a flat disc of radius 0.45 m on the floor under the body's root (the subject's shadow)."""
    from voxpose.voxels.body import Ellipsoids

    root = body.centres.mean(axis=0)
    disc = Ellipsoids(names=("shadow",), centres=np.array([[root[0] + 0.25, 0.0, root[2] + 0.15]]),
                      rotations=np.eye(3)[None], radii=np.array([[0.45, 0.01, 0.35]]))  # fmt: skip
    return render_silhouettes(disc, rig)


def write_studio(directory, rig: Rig, motion, seed: int = 0) -> dict:
    """Write the studio (module docstring); returns the paths written."""
    directory = Path(directory)
    bent = distorted(rig)
    rng = np.random.default_rng(seed)
    height, width = rig.image_size
    for cam in bent:
        path = directory / "calib" / f"{cam.name}.yaml"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(opencv_yaml(cam))
    (directory / "truth").mkdir(parents=True, exist_ok=True)
    save_rig(bent, directory / "truth" / "rig.json")
    back = _background(bent, rng)

    def save(image, path):
        path.parent.mkdir(parents=True, exist_ok=True)
        Image.fromarray(np.clip(np.round(image), 0, 255).astype(np.uint8)).save(path)

    for n in range(5):
        for c, cam in enumerate(bent):
            save(back[c] + rng.normal(0, NOISE, back[c].shape), directory / "background" / cam.name / f"{n:03d}.png")
    ellipsoids, _ = posed_body(motion, rig)
    colours = np.array([[200.0, 40.0, 40.0], [40.0, 60.0, 190.0]])  # shirt and trousers
    for f in range(motion.n_frames):
        body = ellipsoids.frame(f)
        sil = render_silhouettes(body, bent)
        shadow = _shadow(bent, body)
        lower = render_silhouettes(_lower_half(body), bent)
        for c, cam in enumerate(bent):
            image = back[c] * LIGHT
            image[shadow[c]] *= SHADOW
            clothes = np.where(lower[c][..., None], colours[1], colours[0])
            clothes = clothes * (1.0 + 0.15 * np.linspace(-1, 1, width))[None, :, None]  # light from one side
            image[sil[c]] = clothes[sil[c]]
            save(image + rng.normal(0, NOISE, image.shape), directory / "frames" / cam.name / f"{FIRST_FRAME + f}.png")
            mask = directory / "truth" / "silhouettes" / cam.name / f"{FIRST_FRAME + f:06d}.png"
            mask.parent.mkdir(parents=True, exist_ok=True)
            Image.fromarray(sil[c]).save(mask)
    return {"calibration": sorted((directory / "calib").glob("*.yaml")), "frames": directory / "frames",
            "background": directory / "background", "truth": directory / "truth"}  # fmt: skip


def _lower_half(body):
    """The body's solids below its root (trousers)."""
    from voxpose.voxels.body import Ellipsoids

    keep = body.centres[:, 1] < body.centres[:, 1].mean()
    return Ellipsoids(names=tuple(n for n, k in zip(body.names, keep, strict=True) if k), centres=body.centres[keep],
                      rotations=body.rotations[keep], radii=body.radii[keep])  # fmt: skip


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory")
    parser.add_argument("--rig", help="rig file (default: 6 cameras on a circle, 128 x 128)")
    parser.add_argument("--motion", help="motion file (HDF5) from `voxpose motion` (default: a generated walk)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    rig = load_rig(args.rig) if args.rig else circular_rig(focal_px=150.0, width=128, image_height=128, name="six")
    if args.motion:
        from voxpose.motion.data import read_motion

        motion = read_motion(args.motion)
    else:
        from tests.helpers import walk_motion

        motion = walk_motion(8)
    paths = write_studio(args.directory, rig, motion, args.seed)
    print(json.dumps({k: [str(p) for p in v] if isinstance(v, list) else str(v) for k, v in paths.items()}))


if __name__ == "__main__":
    main()
