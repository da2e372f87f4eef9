"""The shared input checks and squared distances: accepted inputs pass unchanged, every rejection names the
input at fault, distances equal a brute-force sum over coordinates."""

import numpy as np
import pytest

from voxpose.errors import VoxposeError
from voxpose.validation import as_rows, integer, positive_number, squared_distances


def test_as_rows_converts_or_keeps_the_dtype():
    ints = np.arange(6).reshape(3, 2)
    rows = as_rows(ints, "x")
    assert rows.dtype == np.float64 and np.array_equal(rows, ints)
    small = np.ones((4, 3), dtype=np.float32)
    assert as_rows(small, "x", 3, dtype=None) is small  # large descriptor sets are never copied
    assert as_rows([[1, 2]], "x").tolist() == [[1.0, 2.0]]


@pytest.mark.parametrize(
    "a, n_cols, message",
    [
        (np.zeros(3), None, "descriptors: expected a 2-D array (rows, columns), got shape (3,)"),
        (np.zeros((0, 3)), None, "descriptors: expected at least one row and one column, got shape (0, 3)"),
        (np.zeros((3, 0)), None, "descriptors: expected at least one row and one column, got shape (3, 0)"),
        (np.zeros((2, 3)), 4, "descriptors: expected 4 columns, got 3"),
        (np.zeros((2, 2), dtype=bool), None, "descriptors: expected real numbers, got dtype bool"),
        (np.zeros((2, 2), dtype=complex), None, "descriptors: expected real numbers, got dtype complex128"),
        (np.array([["a", "b"]]), None, "descriptors: expected real numbers, got dtype <U1"),
    ],
)
def test_as_rows_rejects_with_the_inputs_name(a, n_cols, message):
    with pytest.raises(VoxposeError) as err:
        as_rows(a, "descriptors", n_cols)
    assert str(err.value) == message


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_as_rows_names_the_first_bad_row_beyond_the_first_chunk(bad):
    a = np.zeros((9000, 2), dtype=np.float32)
    a[8500, 1] = a[8700, 0] = bad
    with pytest.raises(VoxposeError, match=r"^x: row 8500 contains NaN or infinite values$"):
        as_rows(a, "x", dtype=None)


def test_positive_number():
    assert positive_number(3, "w") == 3.0 and isinstance(positive_number(3, "w"), float)
    assert positive_number(np.float32(0.5), "w") == 0.5
    for bad in (0, -1.0, np.nan, np.inf, True, "2", None, [1.0]):
        with pytest.raises(VoxposeError) as err:
            positive_number(bad, "kernel width")
        assert str(err.value) == f"kernel width must be positive and finite, got {bad!r}"


def test_integer():
    assert integer(np.int64(4), "n") == 4 and type(integer(np.int64(4), "n")) is int
    assert integer(0, "q", minimum=0) == 0
    for bad, minimum in ((0, 1), (-1, 0), (2.0, 1), (True, 1), ("3", 1), (None, 1)):
        with pytest.raises(VoxposeError) as err:
            integer(bad, "n_r", minimum=minimum)
        assert str(err.value) == f"n_r must be an integer >= {minimum}, got {bad!r}"


def test_squared_distances_match_brute_force():
    rng = np.random.default_rng(1)
    a, b = rng.normal(size=(30, 4)), rng.normal(size=(6, 4))
    reference = np.array([[sum((x - c) ** 2) for c in b] for x in a])
    np.testing.assert_allclose(squared_distances(a, b), reference, rtol=1e-12, atol=1e-12)
    single = squared_distances(a.astype(np.float32), b)  # computed in float64 whatever the input
    assert single.dtype == np.float64
    np.testing.assert_allclose(single, squared_distances(a.astype(np.float32).astype(np.float64), b), rtol=0)
    # rows far from the origin: |a|^2 + |b|^2 - 2 a.b cancels, and the round-off of a row's distance to
    # itself falls below zero (-0.00098 here without the clipping)
    x = np.random.default_rng(0).normal(size=(50, 3)) * 1e4 + 1e6
    assert squared_distances(x, x).min() == 0.0


def test_squared_distances_in_place_give_the_one_line_formula_bit_for_bit():
    # 300 x 2000 entries: the norms are added in three blocks of rows; the formula is the one the in-place
    # version replaced, so every stage that calls it keeps its numbers
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(300, 20)) * 3.0 + 1.0, rng.normal(size=(2000, 20))
    for x, c in ((a, b), (b, a), (a, a)):
        one_line = np.sum(x * x, axis=1)[:, None] + np.sum(c * c, axis=1)[None, :] - 2.0 * (x @ c.T)
        assert np.array_equal(squared_distances(x, c), np.maximum(one_line, 0.0))
    d2 = squared_distances(b, b)
    assert np.array_equal(d2, d2.T)  # a kernel matrix of one set of rows stays exactly symmetric
