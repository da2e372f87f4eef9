"""The bounding box of a capture volume: the intersection of camera frusta, a polytope in three dimensions.

``voxels.carve.capture_bounds`` needs, per subset of cameras, the box around the points every camera of the subset
sees: six linear programs (min and max of x, y and z) over the frusta's half-spaces. In three variables with a few
dozen constraints the optimum of each is a vertex of the polytope, so the box is that of its vertices, found by
solving every 3 x 3 system of three constraint planes and keeping the solutions that satisfy all constraints.
This replaces ``scipy.optimize.linprog`` (HiGHS), whose import alone took 0.2-0.4 s of every voxelize job's CPU,
for the same box (both find the same vertices; the tests compare them to 1e-7 m, HiGHS's own tolerance).

Feasibility allows a relative slack of ``_SLACK`` (a vertex computed in float64 lies on its planes only to
rounding). A region that is not bounded (its recession cone ``{d : A d <= 0}`` holds a direction other than 0,
``_bounded``) or that is empty has no box: ``None``.
"""

import itertools

import numpy as np

_SLACK = 1e-9  # relative feasibility allowance of a computed vertex
_SINGULAR = 1e-12  # |det| of three unit normals below this: (nearly) parallel planes, no vertex


def _vertices(unit: np.ndarray, level: np.ndarray) -> np.ndarray:
    """(V, 3) vertices of ``{x : unit @ x <= level}`` (unit normals): the points where three of the planes meet
    and every constraint holds (to ``_SLACK``); duplicates where more than three planes meet."""
    triples = np.array(list(itertools.combinations(range(len(unit)), 3)), dtype=np.int64).reshape(-1, 3)
    systems = unit[triples]
    regular = np.abs(np.linalg.det(systems)) > _SINGULAR
    points = np.linalg.solve(systems[regular], level[triples[regular]][:, :, None])[:, :, 0]
    excess = points @ unit.T - level
    allowed = _SLACK * (np.abs(level) + np.linalg.norm(points, axis=1)[:, None] + 1.0)
    return points[(excess <= allowed).all(axis=1)]


def _bounded(unit: np.ndarray) -> bool:
    """Whether ``{x : unit @ x <= b}`` is bounded (whatever ``b``): its recession cone ``{d : unit @ d <= 0}``
    is the origin alone. With normals of rank 3 the cone is pointed, and a pointed cone in three dimensions
    other than the origin has an extreme ray where two independent constraint planes meet, along the cross
    product of their normals (one sign or the other); so it is enough to test those."""
    if np.linalg.matrix_rank(unit) < 3:
        return False
    pairs = np.array(list(itertools.combinations(range(len(unit)), 2)), dtype=np.int64)
    rays = np.cross(unit[pairs[:, 0]], unit[pairs[:, 1]])
    length = np.linalg.norm(rays, axis=1)
    rays = rays[length > _SINGULAR] / length[length > _SINGULAR, None]
    slopes = rays @ unit.T
    return not ((slopes <= _SLACK).all(axis=1) | (slopes >= -_SLACK).all(axis=1)).any()


def polytope_box(normals: np.ndarray, offsets: np.ndarray) -> np.ndarray | None:
    """(2, 3) min and max corners of ``{x : normals @ x <= offsets}`` (normals (m, 3), offsets (m,)), or None
    when that region is empty or unbounded."""
    normals = np.asarray(normals, dtype=float)
    scale = np.linalg.norm(normals, axis=1)
    unit, level = normals / scale[:, None], np.asarray(offsets, dtype=float) / scale
    if len(unit) < 4 or not _bounded(unit):
        return None
    points = _vertices(unit, level)
    if not len(points):
        return None
    return np.stack([points.min(axis=0), points.max(axis=0)])
