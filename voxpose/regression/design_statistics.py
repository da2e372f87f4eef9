"""What MVRVM training needs of the design matrix of Eq. 3, built without holding the matrix.

The design matrix ``Phi`` (N x B: a bias column and one Gaussian per candidate centre, ``kernels.design_matrix``)
has one column per training row under Eq. 3, so it grows with N^2: 0.7 GB at 9,400 rows, 3.2 GB at 20,000.
The sequential training (``voxpose.regression.mvrvm_posterior``) uses ``Phi`` only through

- the Gram matrix ``Phi' Phi`` (B x B): a basis function's overlaps with the active ones give its S and Q,
  and a new active function's column of it updates them;
- ``Phi' Y`` (B x P) and ``||y_p||^2``;
- the columns of the active basis functions, for the residuals of a full recomputation.

``DesignStatistics`` accumulates the first two over blocks of rows (kernel values computed block by block and
dropped), so memory is B^2 + block x B rather than N x B, and hands out single columns on demand. The
arithmetic is a regrouping of the products the dense matrix would give (equal to round-off).
"""

import numpy as np

from voxpose.regression.kernels import design_matrix, gaussian_kernel
from voxpose.validation import row_norms

_BLOCK_ELEMENTS = 1 << 22  # kernel values per block of rows (32 MB of float64)


class DesignStatistics:
    """Gram matrix ``gram`` (B, B), ``phity`` = ``Phi' Y`` (B, P) and ``yy`` (P,) of the design matrix of the
    inputs ``x`` (N, d) on the Gaussians at ``centres`` (M, d) of width ``width``, with a leading bias
    column if ``bias`` (B = bias + M); ``column(j)`` is column j of ``Phi``."""

    def __init__(self, x: np.ndarray, centres: np.ndarray, width: float, bias: bool, y: np.ndarray):
        self.x, self.centres, self.width, self.bias = x, centres, width, bias
        self.n, self.n_basis = x.shape[0], int(bias) + centres.shape[0]
        self.gram = np.zeros((self.n_basis, self.n_basis))
        self.phity = np.zeros((self.n_basis, y.shape[1]))
        self.yy = np.sum(y * y, axis=0)
        self.x_norms = row_norms(x)  # for column(): 0.4 of its 0.6 ms per call were these norms (2285 x 200 rows)
        rows = max(1, _BLOCK_ELEMENTS // self.n_basis)
        for start in range(0, self.n, rows):
            block = design_matrix(x[start : start + rows], centres, width, bias)
            self.gram += block.T @ block  # numpy's symmetric rank-k product: exactly symmetric
            self.phity += block.T @ y[start : start + rows]

    def column(self, j: int) -> np.ndarray:
        """Column ``j`` of the design matrix (N,): the bias, or the Gaussian on centre ``j - bias``."""
        if self.bias and j == 0:
            return np.ones(self.n)
        c = j - int(self.bias)
        return gaussian_kernel(self.x, self.centres[c : c + 1], self.width, self.x_norms)[:, 0]
