"""Rotation matrices and Euler angles, vectorised over any leading shape.

Conventions (the BVH ones): an order such as ``"ZYX"`` means intrinsic rotations applied in the order
the channels are listed, ``R = Rz(a0) @ Ry(a1) @ Rx(a2)``, acting on column vectors of the child frame.
Angles are in degrees. Only the six Tait-Bryan orders (three distinct axes) occur in motion capture.
"""

import numpy as np

from voxpose.errors import VoxposeError

_AXIS = {"X": 0, "Y": 1, "Z": 2}


def _check_order(order: str) -> str:
    order = order.upper()
    if len(order) != 3 or set(order) != {"X", "Y", "Z"}:
        raise VoxposeError(f"Euler order must be a permutation of XYZ, got {order!r}")
    return order


def axis_rotation(axis: str, angle_deg) -> np.ndarray:
    """Rotation matrices about one coordinate axis; shape ``angle.shape + (3, 3)``."""
    a = np.deg2rad(np.asarray(angle_deg, dtype=float))
    c, s = np.cos(a), np.sin(a)
    out = np.zeros(a.shape + (3, 3))
    i = _AXIS[axis.upper()]
    j, k = (i + 1) % 3, (i + 2) % 3
    out[..., i, i] = 1.0
    out[..., j, j] = c
    out[..., k, k] = c
    out[..., k, j] = s
    out[..., j, k] = -s
    return out


def euler_to_matrix(angles_deg, order: str) -> np.ndarray:
    """``(..., 3)`` angles in degrees -> ``(..., 3, 3)`` matrices, ``R = R_order[0] @ R_order[1] @ R_order[2]``."""
    order = _check_order(order)
    angles = np.asarray(angles_deg, dtype=float)
    r = axis_rotation(order[0], angles[..., 0])
    r = r @ axis_rotation(order[1], angles[..., 1])
    return r @ axis_rotation(order[2], angles[..., 2])


def matrix_to_euler(matrix, order: str) -> np.ndarray:
    """Inverse of ``euler_to_matrix``: ``(..., 3, 3)`` -> ``(..., 3)`` degrees.

    The middle angle lies in [-90, 90]; the outer two in (-180, 180]. At gimbal lock (middle angle at
    +-90 degrees) the third angle is set to 0 and the first absorbs the remaining rotation.
    """
    order = _check_order(order)
    m = np.asarray(matrix, dtype=float)
    i, j, k = (_AXIS[a] for a in order)
    # sign of the permutation (i, j, k): +1 for cyclic orders such as XYZ, -1 otherwise
    sign = 1.0 if (j - i) % 3 == 1 else -1.0
    sin_b = np.clip(sign * m[..., i, k], -1.0, 1.0)
    b = np.arcsin(sin_b)
    cos_b = np.sqrt(np.maximum(0.0, 1.0 - sin_b**2))
    locked = cos_b < 1e-9
    a = np.arctan2(-sign * m[..., j, k], m[..., k, k])
    c = np.arctan2(-sign * m[..., i, j], m[..., i, i])
    # gimbal lock: put everything in the first angle, read from the k-th column of rows j, j
    a_locked = np.arctan2(sign * m[..., k, j], m[..., j, j])
    a = np.where(locked, a_locked, a)
    c = np.where(locked, 0.0, c)
    return np.rad2deg(np.stack([a, b, c], axis=-1))


def minimal_rotation(a, b) -> np.ndarray:
    """The smallest rotation taking unit vector(s) ``a`` onto ``b``; ``(..., 3)`` -> ``(..., 3, 3)``.

    For opposite vectors the axis is any one perpendicular to ``a`` (chosen deterministically).
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    a, b = np.broadcast_arrays(a, b)
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    v = np.cross(a, b)
    c = np.sum(a * b, axis=-1)
    s = np.linalg.norm(v, axis=-1)
    # axis: v/s, or for (anti)parallel vectors any perpendicular of a
    perp = np.cross(a, np.array([1.0, 0.0, 0.0]))
    small = np.linalg.norm(perp, axis=-1) < 1e-6
    perp = np.where(small[..., None], np.cross(a, np.array([0.0, 1.0, 0.0])), perp)
    axis = np.where((s > 1e-12)[..., None], v / np.maximum(s, 1e-300)[..., None], perp)
    axis = axis / np.linalg.norm(axis, axis=-1, keepdims=True)
    angle = np.arctan2(s, c)
    return axis_angle_to_matrix(axis, angle)


def axis_angle_to_matrix(axis, angle_rad) -> np.ndarray:
    """Rodrigues' formula: unit ``axis`` (..., 3) and ``angle`` (...) in radians -> (..., 3, 3)."""
    axis = np.asarray(axis, dtype=float)
    angle = np.asarray(angle_rad, dtype=float)
    x, y, z = axis[..., 0], axis[..., 1], axis[..., 2]
    zero = np.zeros_like(x)
    k = np.stack([zero, -z, y, z, zero, -x, -y, x, zero], axis=-1).reshape(axis.shape[:-1] + (3, 3))
    s = np.sin(angle)[..., None, None]
    c = np.cos(angle)[..., None, None]
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)


def unwrap_degrees(angles, axis: int = 0) -> np.ndarray:
    """Remove 360-degree jumps along ``axis`` (time), so consecutive values differ by < 180 degrees."""
    return np.rad2deg(np.unwrap(np.deg2rad(np.asarray(angles, dtype=float)), axis=axis))


def euler_to_matrix_per_joint(angles_deg, orders) -> np.ndarray:
    """``(..., J, 3)`` angles with one Euler order per joint (``orders``, length J) -> ``(..., J, 3, 3)``."""
    angles = np.asarray(angles_deg, dtype=float)
    out = np.empty(angles.shape + (3,))
    for order in set(orders):
        cols = [j for j, o in enumerate(orders) if o == order]
        out[..., cols, :, :] = euler_to_matrix(angles[..., cols, :], order)
    return out


def matrix_to_euler_per_joint(matrix, orders) -> np.ndarray:
    """Inverse of ``euler_to_matrix_per_joint``: ``(..., J, 3, 3)`` -> ``(..., J, 3)`` degrees."""
    m = np.asarray(matrix, dtype=float)
    out = np.empty(m.shape[:-1])
    for order in set(orders):
        cols = [j for j, o in enumerate(orders) if o == order]
        out[..., cols, :] = matrix_to_euler(m[..., cols, :, :], order)
    return out
