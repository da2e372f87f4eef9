"""2D shape contexts on contours: rotation equivariance, a brute-force reference, scale invariance, sampling."""

import numpy as np
import pytest

from voxpose.descriptors.contour import boundary_pixels, contour_points, farthest_points, shape_contexts
from voxpose.errors import VoxposeError


def circle(n=120, phase=0.01, radius=50.0):
    theta = phase + 2 * np.pi * np.arange(n) / n
    return radius * np.stack([np.cos(theta), np.sin(theta)], axis=1)


def test_a_circle_rotated_by_one_angular_bin_shifts_every_histogram_by_one_bin():
    # rotating the points by 30 degrees (one of 12 angular bins) maps point i onto point i + n/12: its histogram
    # must be point i's rolled by one angular bin, radial bins unchanged
    n = 120
    sc = shape_contexts(circle(n)).reshape(n, 5, 12)
    rotated = shape_contexts(circle(n, phase=0.01 + np.pi / 6)).reshape(n, 5, 12)
    assert np.allclose(rotated, np.roll(sc, 1, axis=2))
    assert np.allclose(sc[10], np.roll(sc[0], 1, axis=1))
    assert not np.allclose(sc[0], np.roll(sc[0], 1, axis=1))  # not trivially invariant
    # and the radial profile is the same at every point of a circle
    assert np.allclose(sc.sum(axis=2), sc[0].sum(axis=1))


def brute_force(points, n_r=5, n_theta=12, r_inner=0.125, r_outer=2.0):
    n = len(points)
    dists = [np.hypot(*(points[j] - points[i])) for i in range(n) for j in range(n) if i != j]
    scale = np.mean(dists)
    edges = [r_inner * scale * (r_outer / r_inner) ** (k / n_r) for k in range(n_r + 1)]
    out = np.zeros((n, n_r * n_theta))
    for i in range(n):
        for j in range(n):
            if i == j:
                continue
            dx, dy = points[j] - points[i]
            r = np.hypot(dx, dy)
            ring = [k for k in range(n_r) if edges[k] <= r < edges[k + 1]]
            if ring:
                theta = np.degrees(np.arctan2(dy, dx)) % 360
                out[i, ring[0] * n_theta + int(theta // (360 / n_theta))] += 1
    return out / (n - 1)


def test_equals_a_brute_force_histogram_and_is_scale_invariant():
    points = np.random.default_rng(0).uniform(-40, 40, size=(40, 2))
    sc = shape_contexts(points)
    assert np.allclose(sc, brute_force(points))
    assert np.allclose(shape_contexts(3.0 * points + 7.0), sc)
    assert np.allclose(shape_contexts(points, n_r=3, n_theta=8), brute_force(points, n_r=3, n_theta=8))


def test_boundary_pixels_of_a_rectangle_and_even_contour_sampling():
    mask = np.zeros((50, 60), dtype=bool)
    mask[10:30, 5:45] = True  # 20 x 40
    edge = boundary_pixels(mask)
    assert len(edge) == 2 * (20 + 40) - 4
    assert set(map(tuple, edge.astype(int))) == {(c, r) for r in range(10, 30) for c in range(5, 45)
                                                 if r in (10, 29) or c in (5, 44)}  # fmt: skip
    points = contour_points(mask, 30)
    assert len(points) == 30 and len(np.unique(points, axis=0)) == 30
    # farthest-point samples on a perimeter of 116 pixels: no two closer than about half the even spacing
    d = np.hypot(*(points[:, None] - points[None]).transpose(2, 0, 1)) + np.eye(30) * 1e9
    assert d.min() >= 0.5 * 116 / 30
    assert np.array_equal(contour_points(mask, 30), points)  # deterministic
    assert len(contour_points(mask, 500)) == len(edge)  # fewer boundary pixels than asked: all of them
    assert np.array_equal(farthest_points(edge, 3), np.sort(farthest_points(edge, 3)))


def test_degenerate_inputs():
    assert contour_points(np.zeros((10, 10), dtype=bool), 20).shape == (0, 2)
    assert shape_contexts(np.zeros((1, 2))).shape == (1, 60)
    assert not shape_contexts(np.zeros((1, 2))).any()
    with pytest.raises(VoxposeError):
        shape_contexts(np.array([[0.0, np.nan], [1.0, 1.0]]))
    with pytest.raises(VoxposeError):
        shape_contexts(circle(), r_inner=2.0, r_outer=1.0)
    with pytest.raises(VoxposeError):
        boundary_pixels(np.zeros(5, dtype=bool))


def _brute_force_farthest(points, n):
    """Farthest-point sampling written out: each next point maximises the distance to the chosen set, first wins."""
    chosen = [0]
    for _ in range(1, n):
        d = [min(float(((p - points[c]) ** 2).sum()) for c in chosen) for p in points]
        chosen.append(int(np.argmax(d)))
    return np.sort(chosen)


@pytest.mark.parametrize("kernels", ["numba", "numpy"])
def test_farthest_points_equal_a_brute_force_sampling_ties_included(monkeypatch, kernels):
    if kernels == "numba":
        pytest.importorskip("numba")
    monkeypatch.setenv("VOXPOSE_KERNELS", kernels)
    rng = np.random.default_rng(2)
    yy, xx = np.mgrid[:90, :70]
    blob = ((xx - 35) / 20.0) ** 2 + ((yy - 40) / 30.0) ** 2 < 1  # a body and an arm: integer pixels, many ties
    blob |= (np.abs(xx - 55) < 4) & (yy > 10) & (yy < 60)
    for points, n in ((boundary_pixels(blob), 40), (rng.normal(size=(300, 2)), 25), (np.zeros((5, 2)), 3)):
        np.testing.assert_array_equal(farthest_points(points, n), _brute_force_farthest(points, n))


def test_pixel_grid_offsets_on_the_bin_edges_vote_as_the_brute_force_says():
    """Points on a pixel grid (a contour's): offsets straight right, up, left and down lie on angular bin edges
    (0, 90, 180, 270 degrees with 12 bins) and must fall in the bins that start there, as in the reference;
    a grid that also holds diagonal offsets (45 degrees, inside a bin) and offsets both left and right of each
    point (angles from atan2 in (-180, 180], turned to [0, 360))."""
    xs, ys = np.meshgrid(np.arange(6.0), np.arange(5.0))
    points = np.stack([xs.ravel(), ys.ravel()], axis=1) * 3.0 + 10.0
    np.testing.assert_array_equal(shape_contexts(points), brute_force(points))
    np.testing.assert_array_equal(shape_contexts(points, n_theta=8), brute_force(points, n_theta=8))
