"""Real calibrations -> rig files (``voxpose rig import``): OpenCV FileStorage YAML/XML, or 3x4 projection matrices.

OpenCV FileStorage (``cv::FileStorage``, YAML with ``%YAML:1.0`` and ``!!opencv-matrix`` nodes, or XML with
``type_id="opencv-matrix"`` elements): one file per camera, or one file holding a map per camera (the map's key
is the camera's name). A camera is found by its intrinsics under any of the common key names:

* intrinsics ``camera_matrix`` ``CameraMatrix`` ``cameraMatrix`` ``K`` ``M`` ``intrinsic``;
* distortion (optional) ``distortion_coefficients`` ``DistortionCoeffs`` ``distCoeffs`` ``dist`` ``D``;
* rotation ``rvec`` ``R`` ``rotation`` (3 numbers: a Rodrigues vector; 9: a matrix), world -> camera;
* translation ``tvec`` ``T`` ``t`` ``translation``, world -> camera, in the calibration's unit;
* image size ``image_width`` and ``image_height`` (or ``width``/``height``, or ``image_size``/``imageSize``
  as width, height), else ``--size``.

A camera read from a file of its own is named by its ``name`` key, else the file stem; cameras keep the order
given. Projection matrices: a text file of 12 numbers per camera (3 rows of 4, ``#`` comments), each
decomposed as ``P = K [R | t]`` (RQ decomposition, positive focal lengths, P's sign chosen so det R = +1);
cameras are named ``cam0``, ``cam1``, ... The written rig file (format in ``voxpose.voxels.cameras``) keeps the
calibration's numbers and adds ``unit``, ``up`` and ``floor``; a floor not given is estimated from a carved frame
(``estimate_floor``). Anything unreadable is one error naming the file and the key (or line).
"""

import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import yaml
from scipy.linalg import rq
from scipy.spatial.transform import Rotation

from voxpose.errors import VoxposeError
from voxpose.io.text import read_text

KEYS = {
    "K": ("camera_matrix", "CameraMatrix", "cameraMatrix", "K", "M", "intrinsic"),
    "dist": ("distortion_coefficients", "DistortionCoeffs", "distCoeffs", "dist", "D"),
    "rotation": ("rvec", "R", "rotation"),
    "translation": ("tvec", "T", "t", "translation"),
}
_FLOOR_RESOLUTION = 0.05  # metres: the carving that finds the floor (Section 4's moderate resolution)


class _OpenCVLoader(yaml.SafeLoader):
    """PyYAML reading OpenCV's ``!!opencv-matrix`` nodes as nested lists."""


def _opencv_matrix(loader, node):
    value = loader.construct_mapping(node, deep=True)
    try:
        return np.array(value["data"], dtype=float).reshape(int(value["rows"]), int(value["cols"])).tolist()
    except (KeyError, TypeError, ValueError):
        raise yaml.YAMLError("an opencv-matrix without consistent rows, cols and data") from None


_OpenCVLoader.add_constructor("tag:yaml.org,2002:opencv-matrix", _opencv_matrix)


def read_storage(path) -> dict:
    """The top-level map of an OpenCV FileStorage file (YAML or XML), matrices as nested lists."""
    path = Path(path)
    text = read_text(path, "calibration file")
    try:
        if path.suffix.lower() == ".xml" or text.lstrip().startswith("<"):
            return _xml_map(ET.fromstring(text))
        text = re.sub(r"^%YAML[: ]?1\.\d\s*\n", "", text)  # OpenCV writes "%YAML:1.0", a YAML 1.0 directive
        data = yaml.load(text, Loader=_OpenCVLoader)  # noqa: S506 (a SafeLoader with one extra constructor)
    except (yaml.YAMLError, ET.ParseError) as err:
        raise VoxposeError(f"{path}: not an OpenCV calibration file ({str(err).splitlines()[0]})") from None
    if not isinstance(data, dict):
        raise VoxposeError(f"{path}: not an OpenCV calibration file (no top-level map)")
    return data


def _xml_map(root) -> dict:
    out = {}
    for child in root:
        if child.get("type_id") == "opencv-matrix":
            rows, cols = int(child.findtext("rows")), int(child.findtext("cols"))
            out[child.tag] = np.array(child.findtext("data").split(), dtype=float).reshape(rows, cols).tolist()
        elif len(child):
            out[child.tag] = _xml_map(child)
        else:
            words = (child.text or "").split()
            try:
                numbers = [float(w) for w in words]
                out[child.tag] = numbers[0] if len(numbers) == 1 else numbers
            except ValueError:
                out[child.tag] = (child.text or "").strip()
    return out


def _find(entry: dict, what: str):
    for key in KEYS[what]:
        if key in entry:
            return key, entry[key]
    return None, None


def _numbers(value, count, where) -> np.ndarray:
    try:
        array = np.array(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise VoxposeError(f"{where}: expected numbers") from None
    if array.size not in count or not np.isfinite(array).all():
        raise VoxposeError(f"{where}: expected {' or '.join(map(str, count))} finite numbers, got {array.size}")
    return array


def _image_size(entry: dict, size, where):
    for w_key, h_key in (("image_width", "image_height"), ("width", "height")):
        if w_key in entry and h_key in entry:
            return int(entry[w_key]), int(entry[h_key])
    for key in ("image_size", "imageSize"):
        if key in entry:
            w, h = _numbers(entry[key], (2,), f"{where}: key {key!r}")
            return int(w), int(h)
    if size is None:
        raise VoxposeError(f"{where}: no image size (keys image_width/image_height or image_size); pass --size WxH")
    return size


def _camera(entry: dict, name: str, where: str, size) -> dict:
    k_key, k = _find(entry, "K")
    cam = {"name": name}
    cam["width"], cam["height"] = _image_size(entry, size, where)
    cam["K"] = _numbers(k, (9,), f"{where}: key {k_key!r}").reshape(3, 3).tolist()
    d_key, dist = _find(entry, "dist")
    if d_key is not None:
        coeffs = _numbers(dist, (2, 3, 4, 5, 8, 12, 14), f"{where}: key {d_key!r}")
        if np.any(coeffs[5:]):
            raise VoxposeError(f"{where}: key {d_key!r}: rational or thin-prism terms (coefficients 6 on) are not "
                               "supported; voxpose reads k1 k2 p1 p2 k3")  # fmt: skip
        cam["dist"] = coeffs[:5].tolist()
    r_key, rot = _find(entry, "rotation")
    t_key, t = _find(entry, "translation")
    for key, names in ((r_key, "rotation"), (t_key, "translation")):
        if key is None:
            raise VoxposeError(f"{where}: missing key for the {names} ({'/'.join(KEYS[names])})")
    rot = _numbers(rot, (3, 9), f"{where}: key {r_key!r}")
    cam["R"] = (Rotation.from_rotvec(rot).as_matrix() if rot.size == 3 else rot.reshape(3, 3)).tolist()
    cam["t"] = _numbers(t, (3,), f"{where}: key {t_key!r}").tolist()
    return cam


def cameras_from_storage(paths, size=None) -> list:
    """Camera entries (rig-file dicts) of OpenCV FileStorage files (module docstring), in the order given."""
    cameras = []
    for path in map(Path, paths):
        data = read_storage(path)
        if _find(data, "K")[0] is not None:
            cameras.append(_camera(data, str(data.get("name", path.stem)), str(path), size))
            continue
        found = [(key, value) for key, value in data.items() if isinstance(value, dict) and _find(value, "K")[0]]
        if not found:
            raise VoxposeError(f"{path}: no camera found (no key {'/'.join(KEYS['K'])}, at the top or in a map "
                               "per camera)")  # fmt: skip
        cameras.extend(_camera(value, str(key), f"{path}: {key}", size) for key, value in found)
    return cameras


def cameras_from_projections(path, size) -> list:
    """Camera entries of a text file of 3x4 projection matrices (module docstring)."""
    path = Path(path)
    if size is None:
        raise VoxposeError(f"{path}: projection matrices carry no image size; pass --size WxH")
    numbers = []
    lines = read_text(path, "projection matrices").splitlines()
    for number, line in enumerate(lines, start=1):
        for word in line.split("#")[0].replace(",", " ").split():
            try:
                numbers.append(float(word))
            except ValueError:
                raise VoxposeError(f"{path}: line {number}: {word!r} is not a number") from None
    if not numbers or len(numbers) % 12:
        raise VoxposeError(f"{path}: {len(numbers)} numbers; expected 12 (3 rows of 4) per camera")
    cameras = []
    for i, p in enumerate(np.array(numbers).reshape(-1, 3, 4)):
        if not np.isfinite(p).all() or abs(np.linalg.det(p[:, :3])) < 1e-12 * np.abs(p[:, :3]).max() ** 3:
            raise VoxposeError(f"{path}: camera {i}: the left 3x3 block of P is singular")
        if np.linalg.det(p[:, :3]) < 0:
            p = -p
        k, rot = rq(p[:, :3])
        signs = np.diag(np.sign(np.diag(k)))
        k, rot = k @ signs, signs @ rot
        t = np.linalg.solve(k, p[:, 3])
        cameras.append({"name": f"cam{i}", "width": size[0], "height": size[1], "K": (k / k[2, 2]).tolist(),
                        "R": rot.tolist(), "t": t.tolist()})  # fmt: skip
    return cameras


def estimate_floor(rig, frame, scale: float) -> float:
    """Floor height along the up axis in the calibration's unit: the bottom of the lowest occupied layer of one
    frame (silhouettes (C, H, W)) carved at 5 cm by ``rig`` (loaded with floor 0)."""
    from voxpose.voxels.carve import Carver

    ijk = Carver(rig, _FLOOR_RESOLUTION)(frame)
    if not len(ijk):
        raise VoxposeError("rig import: the first frame's silhouettes carve an empty hull; cannot estimate the "
                           "floor (pass --floor)")  # fmt: skip
    return float(ijk[:, 1].min() * _FLOOR_RESOLUTION / scale)
