"""The Gaussian kernel basis of Eq. 3, its width, and the held-out split that chooses kernel settings.

Width convention: ``G(x, x') = exp(-||x - x'||^2 / (2 w^2))``, so ``w`` is a length in feature space (the
standard deviation of the Gaussian bump), directly comparable with pairwise distances between feature
vectors; the default width of the regressors is the median pairwise distance of the training rows.

Section 3 writes the basis of one input as ``phi(x) = [1, G(x, x_1), ..., G(x, x_N)]``: a bias followed
by one Gaussian centred on every training row. ``design_matrix`` builds these rows for many inputs.
"""

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.validation import as_rows, integer, squared_distances


def gaussian_kernel(a: np.ndarray, b: np.ndarray, width: float, a_norms=None) -> np.ndarray:
    """Kernel matrix ``G(a_i, b_j) = exp(-||a_i - b_j||^2 / (2 w^2))``, shape (n, m), computed in place in the
    distance matrix (the same numbers as ``np.exp(-d2 / (2 w^2))``, without two more n x m temporaries);
    ``a_norms``: the rows' squared norms, if known (``voxpose.validation.squared_distances``)."""
    d2 = squared_distances(a, b, a_norms)
    np.divide(d2, -2.0 * width * width, out=d2)
    return np.exp(d2, out=d2)


def design_matrix(x: np.ndarray, centres: np.ndarray, width: float, bias: bool) -> np.ndarray:
    """Rows ``phi(x)`` of Eq. 3 for inputs ``x`` (n, d): ``[1, G(x, c_1), ...]`` (n, bias + m)."""
    k = gaussian_kernel(x, centres, width)
    return np.hstack([np.ones((x.shape[0], 1)), k]) if bias else k


def median_pairwise_distance(x: np.ndarray, max_rows: int = 2000, random_state=None) -> float:
    """Median Euclidean distance between distinct rows of ``x`` (n, d).

    With more than ``max_rows`` rows, the median is taken over a random subset of ``max_rows`` rows
    (``numpy.random.default_rng(random_state)``), which keeps the cost bounded. Raises when the rows do
    not have two distinct values (no scale to take).
    """
    x = as_rows(x, "median pairwise distance: X")
    if x.shape[0] < 2:
        raise VoxposeError("median pairwise distance: needs at least 2 rows")
    if x.shape[0] > max_rows:
        rows = np.random.default_rng(random_state).choice(x.shape[0], size=max_rows, replace=False)
        x = x[np.sort(rows)]
    upper = np.triu_indices(x.shape[0], k=1)
    median = float(np.median(np.sqrt(squared_distances(x, x)[upper])))
    if median <= 0.0:
        raise VoxposeError("median pairwise distance: more than half of the row pairs are identical")
    return median


def holdout_split(n_rows: int, validation_fraction: float = 0.2, groups=None, random_state=None):
    """Split training row indices into a fitting part and a held-out validation part.

    Without ``groups``, a random ``validation_fraction`` of the rows (at least one) is held out. With
    ``groups`` (one label per row, e.g. the motion each frame comes from), whole groups are held out:
    groups are drawn in random order until at least ``validation_fraction`` of the rows are held out,
    never all of them, so frames of one motion are never on both sides (neighbouring frames are nearly
    identical, and splitting them would make validation optimistic).

    Returns
    -------
    fit_rows, val_rows : sorted int arrays partitioning ``range(n_rows)``.
    """
    if not 0.0 < validation_fraction < 1.0:
        raise VoxposeError(f"validation fraction must lie in (0, 1), got {validation_fraction!r}")
    if n_rows < 2:
        raise VoxposeError(f"a held-out split needs at least 2 rows, got {n_rows}")
    rng = np.random.default_rng(random_state)
    if groups is None:
        n_val = min(n_rows - 1, max(1, round(validation_fraction * n_rows)))
        held = np.zeros(n_rows, dtype=bool)
        held[rng.choice(n_rows, size=n_val, replace=False)] = True
    else:
        groups = np.asarray(groups)
        if groups.shape != (n_rows,):
            raise VoxposeError(f"groups: expected one label per row ({n_rows}), got shape {groups.shape}")
        labels, index = np.unique(groups, return_inverse=True)
        if labels.size < 2:
            raise VoxposeError("groups: need at least 2 distinct groups to hold one out")
        sizes = np.bincount(index)
        order = rng.permutation(labels.size)
        # hold out groups in random order until the fraction is reached; the last group always stays
        n_held = int(np.searchsorted(np.cumsum(sizes[order]), validation_fraction * n_rows) + 1)
        held = np.isin(index, order[: min(n_held, labels.size - 1)])
    return np.flatnonzero(~held), np.flatnonzero(held)


def selection_split(n_rows: int, max_rows=None, validation_fraction: float = 0.2, groups=None, random_state=None,
                    who: str = "selection"):  # fmt: skip
    """The rows a hyper-parameter is chosen on: ``holdout_split`` of at most ``max_rows`` of the ``n_rows`` rows,
    drawn at random (seeded by ``random_state``; None: every row), as indices into ``range(n_rows)``.

    The candidates are only ranked on these rows and the chosen one is refitted on every row, so the ranking need
    not pay for all of them: the MVRVM's candidate fits grow like N^2, the kernel ridge's Cholesky like N^3 (six of
    them on 8,200 rows were a third of a real-data regress job). ``select_kernel_width`` and ``KernelRidge`` use
    the same rule, so with the same ``random_state`` they rank on the same rows.

    Returns
    -------
    fit_rows, val_rows : sorted int arrays, disjoint, of at most ``max_rows`` rows together.
    """
    drawn = np.arange(n_rows)
    if max_rows is not None and n_rows > integer(max_rows, f"{who}: max_rows", minimum=2):
        drawn = np.sort(np.random.default_rng(random_state).choice(n_rows, size=max_rows, replace=False))
    fit_rows, val_rows = holdout_split(drawn.size, validation_fraction,
                                       None if groups is None else np.asarray(groups)[drawn], random_state)  # fmt: skip
    return drawn[fit_rows], drawn[val_rows]
