"""Calibrated pinhole cameras and rigs: the views of Section 6 (6 cameras on a circle) and rig files.

Conventions
-----------
World: metres, Y up (``voxpose.motion.canon``). A camera maps a world point X to the camera frame
``X_c = R X + t`` (R: world -> camera rotation), whose axes are x right, y down and z forward (the
optical axis, depth > 0 in front), and to pixels by ``(u, v, 1) ~ K X_c``, i.e. ``P = K [R | t]``.
Pixel coordinates: u is the column, v the row (down); the centre of pixel (row r, column c) is at
``(u, v) = (c, r)``, so a pixel covers ``[c - 0.5, c + 0.5) x [r - 0.5, r + 0.5)`` and the image
spans ``[-0.5, width - 0.5] x [-0.5, height - 0.5]``. A point belongs to the pixel
``(floor(v + 0.5), floor(u + 0.5))``. All cameras of a rig share one image size, so a frame's
silhouettes stack into a (C, H, W) array.

Rig files (JSON, or YAML with a ``.yaml``/``.yml`` suffix)::

    {"name": "circle6",                       # optional: defaults to the file stem
     "cameras": [                             # one object per camera, in silhouette order
       {"name": "cam0",                       # unique; also the camera's silhouette folder name
        "width": 480, "height": 480,          # image size in pixels
        "K": [[fx, s, cx], [0, fy, cy], [0, 0, 1]],    # or "fx", "fy", "cx", "cy" (and "skew")
        "R": [[...], [...], [...]], "t": [tx, ty, tz]  # world -> camera; or instead:
        # "centre": [x, y, z], "look_at": [x, y, z], "up": [0, 1, 0]   (camera centre in metres)
       }, ...]}

``save_rig`` writes K, R and t. ``load_rig`` checks every camera and names the file, the camera and the
key at fault: missing or unknown keys, wrong shapes, non-finite numbers, a degenerate K (non-positive
focal lengths or a last row other than (0, 0, 1)), an R that is not a rotation (orthonormal to 1e-6,
determinant +1), a non-positive or non-integer image size, duplicate names, differing image sizes.

The default rig (``circular_rig``): 6 cameras on a horizontal circle of radius 4 m, 2.0 m high, all
looking at (0, 1.0, 0) (so 14 degrees down), with 480 x 480 images and a 560 px focal length. A 1.75 m
subject standing at the centre spans about 225 px (half the image height) and a voxel of h/60 = 2.9 cm
about 4 px; every point of a cylinder of radius 0.8 m from -0.2 m to 2.4 m high around the centre (raised
arms, jumps, strides) is inside every image with a margin of 20 px (``tests/test_cameras.py``). Motions
travel further than this capture volume (a 200-frame walk covers about 8 m), so the voxeliser re-centres
each frame horizontally on ``Rig.target`` (``voxpose.voxels.voxelize``).
"""

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path

_ORTHO_TOL = 1e-6


@dataclass(frozen=True)
class Camera:
    """One calibrated pinhole camera (see the module docstring for the conventions).

    Attributes
    ----------
    name : unique within its rig.
    K : (3, 3) intrinsics in pixels.
    R : (3, 3) world -> camera rotation; t : (3,) translation in metres.
    width, height : image size in pixels.
    """

    name: str
    K: np.ndarray
    R: np.ndarray
    t: np.ndarray
    width: int
    height: int

    def __post_init__(self):
        object.__setattr__(self, "K", _matrix(self.K, (3, 3), "K"))
        object.__setattr__(self, "R", _matrix(self.R, (3, 3), "R"))
        object.__setattr__(self, "t", _matrix(self.t, (3,), "t"))
        k = self.K
        if k[0, 0] <= 0 or k[1, 1] <= 0:
            raise VoxposeError(f"K is degenerate: focal lengths must be positive, got {k[0, 0]}, {k[1, 1]}")
        if k[1, 0] != 0 or k[2, 0] != 0 or k[2, 1] != 0 or k[2, 2] != 1:
            raise VoxposeError("K must be upper triangular with last row (0, 0, 1)")
        if np.abs(self.R @ self.R.T - np.eye(3)).max() > _ORTHO_TOL or np.linalg.det(self.R) < 0:
            raise VoxposeError("R is not a rotation (orthonormal with determinant +1)")
        for key in ("width", "height"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value <= 0:
                raise VoxposeError(f"{key} must be a positive integer number of pixels, got {value!r}")

    @property
    def P(self) -> np.ndarray:
        """(3, 4) projection matrix ``K [R | t]``."""
        return self.K @ np.hstack([self.R, self.t[:, None]])

    @property
    def centre(self) -> np.ndarray:
        """(3,) camera centre in world coordinates, ``-R^T t``."""
        return -self.R.T @ self.t

    @property
    def forward(self) -> np.ndarray:
        """(3,) unit optical axis in world coordinates (the camera's +z)."""
        return self.R[2].copy()

    def project(self, points, return_depth: bool = False):
        """Pixel coordinates (..., 2) of world points (..., 3); with ``return_depth`` also depth (...).

        Depth is the camera-frame z; a point with depth <= 0 is behind the camera and its pixel
        coordinates are meaningless.
        """
        x_cam = np.einsum("...j,ij->...i", np.asarray(points, dtype=float), self.R) + self.t
        x_img = np.einsum("...j,ij->...i", x_cam, self.K)
        uv = x_img[..., :2] / x_img[..., 2:3]
        return (uv, x_cam[..., 2]) if return_depth else uv


@dataclass(frozen=True)
class Rig:
    """Calibrated cameras in silhouette order, sharing one image size."""

    name: str
    cameras: tuple = field(default_factory=tuple)

    def __post_init__(self):
        object.__setattr__(self, "cameras", tuple(self.cameras))
        if not self.cameras:
            raise VoxposeError(f"rig {self.name}: no cameras")
        names = [c.name for c in self.cameras]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise VoxposeError(f"rig {self.name}: duplicate camera name(s) {', '.join(dup)}")
        first = self.cameras[0]
        for cam in self.cameras[1:]:
            if (cam.width, cam.height) != (first.width, first.height):
                raise VoxposeError(
                    f"rig {self.name}: camera {cam.name} is {cam.width}x{cam.height}, "
                    f"camera {first.name} is {first.width}x{first.height}: all must share one image size"
                )

    def __len__(self) -> int:
        return len(self.cameras)

    def __iter__(self):
        return iter(self.cameras)

    def __getitem__(self, i) -> Camera:
        return self.cameras[i]

    @property
    def names(self) -> tuple:
        return tuple(c.name for c in self.cameras)

    @property
    def image_size(self) -> tuple:
        """(height, width) of every camera's image."""
        return self.cameras[0].height, self.cameras[0].width

    @property
    def projections(self) -> np.ndarray:
        """(C, 3, 4) projection matrices."""
        return np.stack([c.P for c in self.cameras])

    @property
    def target(self) -> np.ndarray:
        """(3,) the point nearest (least squares) to all optical axes: the capture volume's centre.

        For ``circular_rig`` it is the common look-at point. Cameras with parallel axes have no such point.
        """
        eye = np.eye(3)
        lhs = np.zeros((3, 3))
        rhs = np.zeros(3)
        for cam in self.cameras:
            proj = eye - np.outer(cam.forward, cam.forward)  # distance to the axis through the centre
            lhs += proj
            rhs += proj @ cam.centre
        if np.linalg.cond(lhs) > 1e8:
            raise VoxposeError(f"rig {self.name}: the optical axes are parallel, so no capture centre exists")
        return np.linalg.solve(lhs, rhs)


def look_at(centre, target, up=(0.0, 1.0, 0.0)):
    """(R, t) of a camera at ``centre`` looking at ``target`` with image "up" along world ``up``."""
    centre = np.asarray(centre, dtype=float)
    forward = np.asarray(target, dtype=float) - centre
    norm = np.linalg.norm(forward)
    if norm < 1e-9:
        raise VoxposeError("look_at: the camera centre and the look-at point coincide")
    forward /= norm
    right = np.cross(forward, np.asarray(up, dtype=float))
    if np.linalg.norm(right) < 1e-9:
        raise VoxposeError("look_at: the viewing direction is parallel to the up vector")
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    rot = np.stack([right, down, forward])
    return rot, -rot @ centre


def circular_rig(
    n: int = 6,
    radius: float = 4.0,
    height: float = 2.0,
    focal_px: float = 560.0,
    width: int = 480,
    image_height: int = 480,
    target=(0.0, 1.0, 0.0),
    name: str = "circle6",
) -> Rig:
    """``n`` cameras evenly spaced on a horizontal circle, all looking at ``target`` (Section 6).

    Camera ``i`` (named ``cam{i}``) sits at azimuth ``360 i / n`` degrees from +Z towards +X around the
    target, ``radius`` metres away horizontally and ``height`` metres above the floor; images are
    ``width`` x ``image_height`` pixels with square pixels, focal length ``focal_px`` and the principal
    point at the image centre. Defaults: the rig described in the module docstring.
    """
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
        raise VoxposeError(f"circular_rig: n must be a positive integer, got {n!r}")
    if not radius > 0 or not focal_px > 0:
        raise VoxposeError(f"circular_rig: radius and focal_px must be positive, got {radius}, {focal_px}")
    target = np.asarray(target, dtype=float)
    k = np.array([[focal_px, 0.0, (width - 1) / 2], [0.0, focal_px, (image_height - 1) / 2], [0, 0, 1]])
    cameras = []
    for i in range(n):
        phi = 2 * np.pi * i / n
        centre = np.array([target[0] + radius * np.sin(phi), height, target[2] + radius * np.cos(phi)])
        rot, t = look_at(centre, target)
        cameras.append(Camera(f"cam{i}", k, rot, t, width, image_height))
    return Rig(name, cameras)


def _matrix(value, shape, key) -> np.ndarray:
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise VoxposeError(f"{key} must be numbers of shape {shape}") from None
    if array.shape != shape:
        raise VoxposeError(f"{key} has shape {array.shape}, expected {shape}")
    if not np.isfinite(array).all():
        raise VoxposeError(f"{key} has non-finite values")
    return array


_INTRINSIC_KEYS = ("fx", "fy", "cx", "cy")
_KNOWN_KEYS = {"name", "width", "height", "K", "skew", "R", "t", "centre", "look_at", "up", *_INTRINSIC_KEYS}


def _camera_from_dict(entry) -> Camera:
    if not isinstance(entry, dict):
        raise VoxposeError("must be an object")
    unknown = sorted(set(entry) - _KNOWN_KEYS)
    if unknown:
        raise VoxposeError(f"unknown key {unknown[0]!r} (known: {', '.join(sorted(_KNOWN_KEYS))})")
    for key in ("name", "width", "height"):
        if key not in entry:
            raise VoxposeError(f"missing key {key!r}")
    if not isinstance(entry["name"], str) or not entry["name"]:
        raise VoxposeError(f"name must be a non-empty string, got {entry['name']!r}")
    if "K" in entry:
        k = entry["K"]
    elif all(key in entry for key in _INTRINSIC_KEYS):
        fx, fy, cx, cy = (_matrix(entry[key], (), key) for key in _INTRINSIC_KEYS)
        skew = _matrix(entry.get("skew", 0.0), (), "skew")
        k = [[fx, skew, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]]
    else:
        missing = [key for key in _INTRINSIC_KEYS if key not in entry]
        raise VoxposeError(f"missing key 'K' (or {', '.join(repr(m) for m in missing)})")
    if "R" in entry or "t" in entry:
        for key in ("R", "t"):
            if key not in entry:
                raise VoxposeError(f"missing key {key!r} (R and t come together)")
        rot, t = entry["R"], entry["t"]
    elif "centre" in entry or "look_at" in entry:
        for key in ("centre", "look_at"):
            if key not in entry:
                raise VoxposeError(f"missing key {key!r} (centre and look_at come together)")
        centre = _matrix(entry["centre"], (3,), "centre")
        target = _matrix(entry["look_at"], (3,), "look_at")
        up = _matrix(entry.get("up", [0.0, 1.0, 0.0]), (3,), "up")
        rot, t = look_at(centre, target, up)
    else:
        raise VoxposeError("missing key 'R' and 't' (or 'centre' and 'look_at')")
    return Camera(entry["name"], k, rot, t, entry["width"], entry["height"])


def load_rig(path) -> Rig:
    """Read a rig file (format in the module docstring); every error names the file, camera and key."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as err:
        raise VoxposeError(f"{path}: cannot read rig file ({err.strerror})") from None
    except UnicodeDecodeError:
        raise VoxposeError(f"{path}: not a valid rig file (not JSON or YAML text)") from None
    try:
        data = yaml.safe_load(text) if path.suffix.lower() in (".yaml", ".yml") else json.loads(text)
    except (json.JSONDecodeError, yaml.YAMLError) as err:
        first_line = str(err).splitlines()[0]
        raise VoxposeError(f"{path}: not a valid rig file ({first_line})") from None
    if not isinstance(data, dict) or "cameras" not in data:
        raise VoxposeError(f"{path}: missing key 'cameras' (a list with one object per camera)")
    entries = data["cameras"]
    if not isinstance(entries, list) or not entries:
        raise VoxposeError(f"{path}: 'cameras' must be a non-empty list")
    cameras = []
    for i, entry in enumerate(entries):
        label = f"cameras[{i}]"
        if isinstance(entry, dict) and isinstance(entry.get("name"), str):
            label += f" ({entry['name']})"
        try:
            cameras.append(_camera_from_dict(entry))
        except VoxposeError as err:
            raise VoxposeError(f"{path}: {label}: {err}") from None
    name = data.get("name", path.stem)
    try:
        return Rig(str(name), cameras)
    except VoxposeError as err:
        raise VoxposeError(f"{path}: {err}") from None


def rig_from_config(cfg: dict) -> Rig:
    """The rig of a config ``rig`` section: its calibration ``file``, else a ``circular_rig`` of its parameters."""
    if cfg.get("file"):
        return load_rig(cfg["file"])
    return circular_rig(
        n=cfg["n_cameras"],
        radius=cfg["radius"],
        height=cfg["height"],
        focal_px=cfg["focal_px"],
        width=cfg["width"],
        image_height=cfg["image_height"],
        target=(0.0, cfg["target_height"], 0.0),
        name=cfg["name"],
    )


def rig_json(rig: Rig) -> str:
    """The calibration file's text of ``rig`` (K, R, t and image size per camera): what ``save_rig`` writes."""
    data = {
        "name": rig.name,
        "cameras": [
            {
                "name": cam.name,
                "width": int(cam.width),
                "height": int(cam.height),
                "K": cam.K.tolist(),
                "R": cam.R.tolist(),
                "t": cam.t.tolist(),
            }
            for cam in rig.cameras
        ],
    }
    return json.dumps(data, indent=2) + "\n"


def save_rig(rig: Rig, path) -> None:
    """Write ``rig``'s calibration file (``rig_json``), atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(rig_json(rig))
