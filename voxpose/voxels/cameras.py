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

Rig files (JSON, or YAML with a ``.yaml``/``.yml`` suffix): the one place their format is described::

    {"name": "studio",                        # optional: defaults to the file stem
     "unit": "mm",                            # optional: metres per length unit (a number, or m dm cm mm); 1
     "up": "+z", "floor": 0.0,                # optional: the world's up axis (+x -x +y -y +z -z or a vector)
                                              # and the floor's height along it, in the file's unit; +y and 0
     # or instead of up/floor: "world": 4x4 rigid transform from the file's world to a Y-up world
     #                         whose floor is y = 0, in the file's unit
     "cameras": [                             # one object per camera, in silhouette order
       {"name": "cam0",                       # unique; also the camera's silhouette folder name
        "width": 480, "height": 480,          # image size in pixels
        "K": [[fx, s, cx], [0, fy, cy], [0, 0, 1]],    # or "fx", "fy", "cx", "cy" (and "skew")
        "dist": [k1, k2, p1, p2, k3],         # optional: OpenCV distortion, 2 to 5 coefficients (voxels.lens)
        "R": [[...], [...], [...]], "t": [tx, ty, tz]  # world -> camera, t in the file's unit; or instead:
        # "centre": [x, y, z], "look_at": [x, y, z], "up": [0, 1, 0]   (in the file's world and unit)
       }, ...]}

Example: a studio calibrated in millimetres on a floor checkerboard with Z up::

    {"unit": "mm", "up": "+z", "floor": 0,
     "cameras": [{"name": "c1", "width": 1280, "height": 720,
                  "K": [[1100, 0, 640], [0, 1100, 360], [0, 0, 1]], "dist": [-0.21, 0.08, 0, 0, 0],
                  "R": [[1, 0, 0], [0, 0, -1], [0, 1, 0]], "t": [0, 1000, 4000]}]}

``load_rig`` returns the rig in voxpose's world (metres, Y up, floor at y = 0): with ``unit`` s, a rotation
A taking the file's up axis to +Y (the smallest such rotation; for a down axis, -y or a vector opposite to
+Y, the half turn about X) and the floor f, a file point X is the world point ``s (A X - f e_y)``, so each
camera's ``R`` becomes ``R A^T`` and ``t`` becomes ``s t + R A^T (0, s f, 0)``. A ``world`` matrix
``[[A, a], [0, 1]]`` gives ``s (A X + a)`` likewise. Distortion acts on normalised coordinates and needs no
change. A rig without these keys is used exactly as written. ``rig import`` (``voxpose.voxels.calibration``)
writes such files from OpenCV calibrations.

``save_rig`` writes K, R, t (and ``dist`` for distorted cameras) in the world of voxpose. ``load_rig`` checks
every camera and names the file, the camera and the key at fault: missing or unknown keys, wrong shapes,
non-finite numbers, a degenerate K (non-positive focal lengths or a last row other than (0, 0, 1)), an R that
is not a rotation (orthonormal to 1e-4, determinant +1; a rotation off by more than 1e-6, as printed
calibrations are, is re-orthonormalised to the nearest rotation with a log line), a non-positive or
non-integer image size, duplicate names, differing image sizes.

The default rig (``circular_rig``): 6 cameras on a horizontal circle of radius 4 m, 2.0 m high, all
looking at (0, 1.0, 0) (so 14 degrees down), with 480 x 480 images and a 560 px focal length. A 1.75 m
subject standing at the centre spans about 225 px (half the image height) and a voxel of h/60 = 2.9 cm
about 4 px; every point of a cylinder of radius 0.8 m from -0.2 m to 2.4 m high around the centre (raised
arms, jumps, strides) is inside every image with a margin of 20 px (``tests/test_cameras.py``). Motions
travel further than this capture volume (a 200-frame walk covers about 8 m), so the voxeliser re-centres
each frame horizontally on ``Rig.target`` (``voxpose.voxels.voxelize``).
"""

import json
import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from voxpose.errors import VoxposeError
from voxpose.io.atomic import atomic_path
from voxpose.io.text import read_text
from voxpose.voxels import lens

log = logging.getLogger(__name__)

_ORTHO_TOL = 1e-4  # rotations printed to a few digits are accepted ...
_REORTHONORMALISE = 1e-6  # ... and those off by more than this are replaced by the nearest rotation
UNITS = {"m": 1.0, "dm": 0.1, "cm": 0.01, "mm": 0.001}
AXES = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0), "+z": (0, 0, 1), "-z": (0, 0, -1)}


@dataclass(frozen=True)
class Camera:
    """One calibrated pinhole camera (see the module docstring for the conventions).

    Attributes
    ----------
    name : unique within its rig.
    K : (3, 3) intrinsics in pixels.
    R : (3, 3) world -> camera rotation; t : (3,) translation in metres.
    width, height : image size in pixels.
    dist : (5,) OpenCV distortion ``(k1, k2, p1, p2, k3)`` (``voxpose.voxels.lens``); default none (zeros).
    """

    name: str
    K: np.ndarray
    R: np.ndarray
    t: np.ndarray
    width: int
    height: int
    dist: np.ndarray = None

    def __post_init__(self):
        object.__setattr__(self, "K", _matrix(self.K, (3, 3), "K"))
        object.__setattr__(self, "R", _matrix(self.R, (3, 3), "R"))
        object.__setattr__(self, "t", _matrix(self.t, (3,), "t"))
        dist = np.zeros(lens.N_COEFFICIENTS) if self.dist is None else lens.coefficients(self.dist)
        object.__setattr__(self, "dist", dist)
        k = self.K
        if k[0, 0] <= 0 or k[1, 1] <= 0:
            raise VoxposeError(f"K is degenerate: focal lengths must be positive, got {k[0, 0]}, {k[1, 1]}")
        if k[1, 0] != 0 or k[2, 0] != 0 or k[2, 1] != 0 or k[2, 2] != 1:
            raise VoxposeError("K must be upper triangular with last row (0, 0, 1)")
        off = np.abs(self.R @ self.R.T - np.eye(3)).max()
        if off > _ORTHO_TOL or np.linalg.det(self.R) < 0:
            raise VoxposeError(f"R is not a rotation (orthonormal to {_ORTHO_TOL:g} with determinant +1; "
                               f"off by {off:.2g})")  # fmt: skip
        if off > _REORTHONORMALISE:
            u, _, vt = np.linalg.svd(self.R)
            object.__setattr__(self, "R", u @ vt)
            log.info("camera %s: R is orthonormal to %.2g only; replaced by the nearest rotation", self.name, off)
        for key in ("width", "height"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value <= 0:
                raise VoxposeError(f"{key} must be a positive integer number of pixels, got {value!r}")

    @property
    def distorted(self) -> bool:
        """Whether the camera has lens distortion."""
        return bool(self.dist.any())

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
        coordinates are meaningless. Lens distortion, if any, is applied (``voxpose.voxels.lens``).
        """
        x_cam = np.einsum("...j,ij->...i", np.asarray(points, dtype=float), self.R) + self.t
        if self.distorted:
            x, y = lens.distort(x_cam[..., 0] / x_cam[..., 2], x_cam[..., 1] / x_cam[..., 2], self.dist)
            uv = np.stack([self.K[0, 0] * x + self.K[0, 1] * y + self.K[0, 2], self.K[1, 1] * y + self.K[1, 2]], -1)
            return (uv, x_cam[..., 2]) if return_depth else uv
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
    def distorted(self) -> bool:
        """Whether any camera has lens distortion (then carving and rendering go through ``lens.PinholeTwin``)."""
        return any(c.distorted for c in self.cameras)

    def without_distortion(self) -> "Rig":
        """The same cameras with the distortion dropped (what ignoring it would carve)."""
        return Rig(self.name, [Camera(c.name, c.K, c.R, c.t, c.width, c.height) for c in self.cameras])

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
_KNOWN_KEYS = {"name", "width", "height", "K", "skew", "dist", "R", "t", "centre", "look_at", "up", *_INTRINSIC_KEYS}


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
    dist = entry.get("dist")
    if dist is not None and (not isinstance(dist, list) or not all(isinstance(d, int | float) for d in dist)):
        raise VoxposeError("dist must be a list of 2 to 5 numbers (k1 k2 [p1 p2 [k3]])")
    return Camera(entry["name"], k, rot, t, entry["width"], entry["height"], dist)


def unit_scale(value) -> float:
    """Metres per unit of a ``unit`` key or ``--unit`` option: a positive number or one of ``UNITS``."""
    if isinstance(value, str) and value.strip().lower() in UNITS:
        return UNITS[value.strip().lower()]
    try:
        scale = float(value)
    except (TypeError, ValueError):
        scale = float("nan")
    if not (np.isfinite(scale) and scale > 0):
        raise VoxposeError(f"unit must be metres per unit (a positive number) or one of {', '.join(UNITS)}, "
                           f"got {value!r}")  # fmt: skip
    return scale


def up_rotation(value) -> np.ndarray:
    """The rotation A taking an ``up`` axis (+x -x +y -y +z -z or a 3-vector) to +Y: the smallest one, or for
    an axis opposite to +Y the half turn about X."""
    if isinstance(value, str):
        if value.strip().lower() not in AXES:
            raise VoxposeError(f"up must be one of {', '.join(AXES)} or a 3-vector, got {value!r}")
        value = AXES[value.strip().lower()]
    up = _matrix(value, (3,), "up")
    norm = np.linalg.norm(up)
    if norm == 0:
        raise VoxposeError("up must be a non-zero vector")
    up = up / norm
    y = np.array([0.0, 1.0, 0.0])
    axis = np.cross(up, y)
    sin, cos = np.linalg.norm(axis), float(up @ y)
    if sin < 1e-12:
        return np.eye(3) if cos > 0 else np.diag([1.0, -1.0, -1.0])
    axis /= sin
    cross = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + sin * cross + (1 - cos) * cross @ cross


def world_alignment(data: dict):
    """(s, A, a) of a rig file's ``unit``, ``up``/``floor`` or ``world`` keys: world point ``s (A X + a)``;
    ``None`` when the file has none of them (the rig is used as written)."""
    if not any(key in data for key in ("unit", "up", "floor", "world")):
        return None
    scale = unit_scale(data.get("unit", 1.0))
    if "world" in data:
        if "up" in data or "floor" in data:
            raise VoxposeError("world: give either 'world' or 'up'/'floor', not both")
        world = _matrix(data["world"], (4, 4), "world")
        if np.abs(world[3] - [0, 0, 0, 1]).max() > 0:
            raise VoxposeError("world: the last row must be (0, 0, 0, 1)")
        rot, shift = world[:3, :3], world[:3, 3]
        if np.abs(rot @ rot.T - np.eye(3)).max() > _ORTHO_TOL or np.linalg.det(rot) < 0:
            raise VoxposeError("world: the 3x3 part must be a rotation (rigid, right-handed)")
        return scale, rot, shift
    floor = _matrix(data.get("floor", 0.0), (), "floor")
    return scale, up_rotation(data.get("up", "+y")), np.array([0.0, -float(floor), 0.0])


def _is_identity(scale, rot, shift) -> bool:
    return scale == 1.0 and np.array_equal(rot, np.eye(3)) and not shift.any()


def aligned(camera: Camera, scale: float, rot: np.ndarray, shift: np.ndarray) -> Camera:
    """``camera`` of a world X seen in voxpose's world ``scale (rot X + shift)`` (module docstring)."""
    r = camera.R @ rot.T
    t = scale * camera.t - scale * (r @ shift)
    return Camera(camera.name, camera.K, r, t, camera.width, camera.height, camera.dist)


def load_rig(path) -> Rig:
    """Read a rig file (format in the module docstring); every error names the file, camera and key."""
    path = Path(path)
    text = read_text(path, "rig file")
    try:
        data = yaml.safe_load(text) if path.suffix.lower() in (".yaml", ".yml") else json.loads(text)
    except (json.JSONDecodeError, yaml.YAMLError) as err:
        first_line = str(err).splitlines()[0]
        raise VoxposeError(f"{path}: not a valid rig file ({first_line})") from None
    return rig_from_dict(data, str(path), path.stem)


def rig_from_dict(data, label: str, default_name: str = "rig") -> Rig:
    """The rig of a rig file's parsed contents; errors start with ``label`` (the file)."""
    if not isinstance(data, dict) or "cameras" not in data:
        raise VoxposeError(f"{label}: missing key 'cameras' (a list with one object per camera)")
    try:
        alignment = world_alignment(data)
    except VoxposeError as err:
        raise VoxposeError(f"{label}: {err}") from None
    entries = data["cameras"]
    if not isinstance(entries, list) or not entries:
        raise VoxposeError(f"{label}: 'cameras' must be a non-empty list")
    cameras = []
    for i, entry in enumerate(entries):
        where = f"cameras[{i}]"
        if isinstance(entry, dict) and isinstance(entry.get("name"), str):
            where += f" ({entry['name']})"
        try:
            cameras.append(_camera_from_dict(entry))
        except VoxposeError as err:
            raise VoxposeError(f"{label}: {where}: {err}") from None
    if alignment is not None and not _is_identity(*alignment):  # identity: the cameras as written, bit for bit
        cameras = [aligned(cam, *alignment) for cam in cameras]
    name = data.get("name", default_name)
    try:
        return Rig(str(name), cameras)
    except VoxposeError as err:
        raise VoxposeError(f"{label}: {err}") from None


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
            | ({"dist": cam.dist.tolist()} if cam.distorted else {})
            for cam in rig.cameras
        ],
    }
    return json.dumps(data, indent=2) + "\n"


def save_rig(rig: Rig, path) -> None:
    """Write ``rig``'s calibration file (``rig_json``), atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(rig_json(rig))
