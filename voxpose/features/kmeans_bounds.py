"""Lloyd's assignment step without the distances it can prove unchanged: Hamerly's (2010) bounds.

Lloyd's k-means recomputes the distance of every row to every centre at each iteration, although after the
first few iterations the centres barely move and almost no row changes cluster. Hamerly ("Making k-means even
faster", SDM 2010) keeps two bounds per row: ``u`` above the distance to its own centre ``a`` and ``l`` below
the distance to every other centre. When the centres move by ``delta_j``, ``u`` grows by ``delta_a`` and ``l``
shrinks by the largest ``delta`` of another centre (triangle inequality). A row with ``u < max(l, s_a)``, where
``s_a`` is half the distance from ``a`` to its nearest other centre, cannot have changed cluster and is skipped;
otherwise ``u`` is tightened to the exact distance and the test repeated, and only the rows still in doubt get
their distances to all centres, as Lloyd computes them (``validation.squared_distances``).

The same labels as Lloyd's, not an approximation: the test is made on squared distances with a margin of
``1e-9 (|x|^2 + max_j |c_j|^2)``, about 10^4 times the round-off of a computed squared distance (one d-term dot
product, ``|x|^2 + |c|^2 - 2 x.c``) and of the bounds' own updates, so a skipped row is strictly nearer its own
centre in the numbers Lloyd would compute as well. Rows in doubt are computed with the same formula and the
same precomputed row norms. (A BLAS may round a product of fewer than about 8 rows differently from a larger
one, by ~1e-14 of |x|^2; a label could then differ from Lloyd's only at such an exact tie between two centres.)
``tests/features/test_kmeans.py`` checks labels, centres and iteration counts against plain Lloyd iterations.
"""

import numpy as np

from voxpose.validation import row_norms, squared_distances

MARGIN = 1e-9  # relative margin of the skip test, on squared distances (see the module docstring)


class BoundedAssignment:
    """Nearest centres of the rows of ``X`` for a sequence of centre sets, with Hamerly's bounds carried over.

    ``assign(centres)`` returns the (n,) labels Lloyd's ``nearest_centres`` would; each call after the first
    updates the bounds by how far each centre moved since the previous call. ``recomputed`` is how many rows
    of the last call needed all their distances.
    """

    def __init__(self, X, chunk_size: int):
        self._x, self._chunk = X, chunk_size
        n = X.shape[0]
        self._row_sq = np.concatenate(
            [row_norms(np.asarray(X[s : s + chunk_size], dtype=np.float64)) for s in range(0, n, chunk_size)]
        )
        self._centres = None
        self.labels = np.zeros(n, dtype=np.intp)
        self._upper, self._lower = np.zeros(n), np.zeros(n)
        self.recomputed = n

    def assign(self, centres: np.ndarray) -> np.ndarray:
        """Labels of all rows under ``centres`` (K, d), float64."""
        centres = np.array(centres, dtype=np.float64)
        doubt = np.arange(self._x.shape[0])
        if self._centres is not None:
            self._move(centres)
            between = squared_distances(centres, centres)
            np.fill_diagonal(between, np.inf)
            half_gap = 0.5 * np.sqrt(np.min(between, axis=1))
            margin_of = MARGIN * (self._row_sq + np.max(row_norms(centres)))
            doubt = doubt[self._unsettled(doubt, half_gap, margin_of)]
            self._tighten(doubt, centres)
            doubt = doubt[self._unsettled(doubt, half_gap, margin_of)]
        self._nearest_two(doubt, centres)
        self.recomputed = doubt.size
        self._centres = centres
        return self.labels.copy()

    def _move(self, centres):
        """Widen the bounds by how far each centre moved since the last call."""
        delta = np.sqrt(row_norms(centres - self._centres))
        self._upper += delta[self.labels]
        if delta.size > 1:
            first = int(np.argmax(delta))
            second = float(np.max(np.delete(delta, first)))
            self._lower -= np.where(self.labels == first, second, delta[first])

    def _unsettled(self, rows, half_gap, margin_of):
        """Mask over ``rows``: those whose label the bounds do not settle (``u^2 + margin >= max(l, s_a)^2``)."""
        bound = np.maximum(half_gap[self.labels[rows]], self._lower[rows])
        return ~(self._upper[rows] ** 2 + margin_of[rows] < bound * bound)

    def _tighten(self, rows, centres):
        """Set ``u`` to the exact distance from each of ``rows`` to its own centre."""
        for s in range(0, rows.size, self._chunk):
            part = rows[s : s + self._chunk]
            diff = np.asarray(self._x[part], dtype=np.float64) - centres[self.labels[part]]
            self._upper[part] = np.sqrt(row_norms(diff))

    def _nearest_two(self, rows, centres):
        """Labels and both bounds of ``rows`` from their distances to all centres (Lloyd's computation)."""
        contiguous = rows.size == self._x.shape[0]
        for s in range(0, rows.size, self._chunk):
            part = slice(s, s + self._chunk) if contiguous else rows[s : s + self._chunk]
            d2 = squared_distances(self._x[part], centres, self._row_sq[part])
            best = np.argmin(d2, axis=1)
            index = np.arange(len(d2))
            self.labels[part] = best
            self._upper[part] = np.sqrt(d2[index, best])
            d2[index, best] = np.inf
            self._lower[part] = np.sqrt(np.min(d2, axis=1))
