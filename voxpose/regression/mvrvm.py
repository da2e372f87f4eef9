"""The Multi-Variate Relevance Vector Machine of Section 3 (Eqs. 2-3), trained by fast marginal-likelihood
maximisation.

Model (Thayananthan et al. 2006, "Multivariate relevance vector machines for tracking", ECCV): P outputs
``y = W phi(x) + xi`` (Eq. 2) with the basis ``phi`` of Eq. 3 (a bias and one Gaussian per training row,
``voxpose.regression.kernels``); noise ``xi_p ~ N(0, 1/beta_p)``, one precision per output (Eq. 2's diagonal
covariance); weights ``w_mp ~ N(0, 1/alpha_m)``, one precision per basis function *shared by all P
outputs*, so a basis function is relevant for all outputs or for none and the model keeps one set of
relevance vectors (the "zero columns of W" of Section 3).

The marginal likelihood, its sparsity and quality factors and the optimal shared precision of one basis
function are in ``voxpose.regression.mvrvm_alpha``; the posterior and its rank-one updates in
``voxpose.regression.mvrvm_posterior``.

Training (Tipping & Faul 2003, Sec. 4, with the shared alpha). Start from the bias alone
(``MVRVM._bias_start``; the empty model without a bias; with ``fit(start=...)``, from another fit's relevance
vectors, precisions and noise: ``MVRVM._warm_start``). Each iteration finds the move with the largest gain in
``L``: add an inactive basis function at its optimal alpha, re-estimate an active one, or delete one (never
the last). Active basis functions are ranked by deletion and by two Newton steps towards their nearest
optimum, and the best-ranked re-estimate then goes to its global optimum; inactive ones go through branch and
bound with two cheap upper bounds on ``max l`` (``series_bound``, ``mode_bounds`` on the modes, then on a
finer grid), so only the few whose bound beats the best gain so far are solved exactly. Moves update ``mu_p``,
``S``, ``Q`` and the covariances of every output by the rank-one formulas of Tipping & Faul's appendix.
Termination (SparseBayes's rule) is proposed when no move raises ``L``, or when the best move is a re-estimate
changing ``log alpha`` by less than ``tol`` and no addition or deletion would raise ``L`` (all candidates then
solved exactly); it stands when the noise re-estimate changes no ``log beta_p`` by ``tol_beta`` or more.
``max_iter`` bounds the iterations.

Noise: per output, Tipping's re-estimate ``beta_p = (N - gamma_p) / ||y_p - Phi mu_p||^2`` with
``gamma_p = sum_m (1 - alpha_m Sigma_p,mm)``, capped at ``beta_max / v_p`` (``v_p`` the variance of output
p: near-noise-free targets would otherwise drive ``beta_p`` to infinity; SparseBayes's BetaMaxFactor). It
is a fixed-point step and can overshoot, so the EM step ``N / (||y_p - Phi mu_p||^2 + gamma_p / beta_p)``
is evaluated too and the value (old, re-estimate or EM) with the largest ``L_p`` is kept: ``L`` never
decreases. The noise is re-estimated after each of the first 10 iterations, at termination proposals,
and otherwise when the re-estimate would change some ``log beta_p`` by more than ``tol``, checked every
``max(beta_update_every, k / P)`` iterations (``k`` active basis functions): a re-estimate needs a full
recomputation, which costs about as much as ``k / P`` moves.

Candidate subsets (``max_candidates``; the only departure from Eq. 3, off by default): Eq. 3 centres one
Gaussian on every training row, so the design matrix is N x N and every addition costs O(N^2); on a real
library (10^4 rows) that is gigabytes and hours. With ``max_candidates = M < N`` the Gaussians are centred
on M rows drawn at random (seeded by ``random_state``; plus a warm start's relevance vectors) while the
likelihood still sums over all N rows: the design matrix is N x M, the basis functions are a random
subset of Eq. 3's, and the model is the same MVRVM on fewer candidate relevance vectors. With ``M >= N``
(or None) it is exactly Eq. 3.

A candidate almost collinear with an active basis function (cosine above ``alignment_max``; of the centred
columns when there is a bias, ``Posterior``) is not added, as in SparseBayes, whose control settings (initial
noise at 10 % of the target standard deviation, MinDeltaLogAlpha, MinDeltaLogBeta, BetaMaxFactor,
AlignmentMax, 10 initial noise updates) are the defaults here.
"""

import logging
import warnings

import numpy as np

from voxpose.errors import ConvergenceWarning, VoxposeError
from voxpose.regression.design_statistics import DesignStatistics
from voxpose.regression.kernels import design_matrix, median_pairwise_distance, selection_split
from voxpose.regression.mvrvm_alpha import contribution, mode_bounds, newton_ascent, optimal_alpha, series_bound
from voxpose.regression.mvrvm_posterior import Posterior
from voxpose.validation import as_rows, check_fitted, integer, positive_number

log = logging.getLogger(__name__)

_SNR_INIT = 100.0  # initial beta_p * v_p: noise standard deviation 10 % of the target's (SparseBayes)
_MIN_GAIN = 1e-8  # a move must raise log L by more than this (nats): smaller is round-off
_BATCH = 32  # basis functions solved exactly per batch in the branch and bound
_SUBDIVISIONS = 4  # grid points per interval between modes for the finer bounds (mode_bounds)
_RANK_NEWTON = 2  # Newton steps ranking the active basis functions' re-estimates
_BETA_UPDATE_START = 10  # noise re-estimated after each of the first iterations (SparseBayes)
_MIN_CORRECTIONS = 32  # rank-one covariance terms allowed before a recomputation, at least


class MVRVM:
    """Multi-Variate Relevance Vector Machine regression (Section 3; Thayananthan et al. 2006).

    Parameters
    ----------
    kernel_width : width ``w`` of ``exp(-||x - x'||^2 / (2 w^2))``, or ``"median"``: the median pairwise
        distance of the training rows.
    kernel : ``"rbf"``, the Gaussian kernel of ``voxpose.regression.kernels`` (the only kernel the paper uses).
    bias : include the constant basis function of Eq. 3.
    max_iter : maximum number of iterations (one move or noise update each).
    tol : termination threshold on the change of ``log alpha`` of the best re-estimate (SparseBayes's
        MinDeltaLogAlpha).
    tol_beta : termination threshold on changes of ``log beta_p`` (SparseBayes's MinDeltaLogBeta).
    beta_max : cap on ``beta_p`` times the variance of output p (a signal-to-noise ratio).
    beta_update_every : after the first 10 iterations (which all re-estimate the noise), the fewest
        iterations between checks of the noise re-estimate; checks are ``max(beta_update_every, k / P)``
        iterations apart for ``k`` active basis functions.
    alignment_max : cosine above which a candidate counts as collinear with an active basis function.
    max_candidates : at most this many training rows carry a candidate Gaussian (drawn at random); None:
        every row (Eq. 3). See the module docstring.
    random_state : seed for the row subset of the median distance when there are more than 2000 rows, and
        for the candidate rows.

    Attributes
    ----------
    relevance_ : (R,) indices of the training rows whose Gaussians were kept, increasing.
    relevance_vectors_ : (R, d) those training rows.
    has_bias_ : whether the bias basis function was kept.
    coef_ : (has_bias_ + R, P) posterior mean weights: bias row first when kept, then ``relevance_`` order.
    alpha_ : (has_bias_ + R,) weight precisions, same order.
    sigma_ : (P, has_bias_ + R, has_bias_ + R) posterior weight covariance per output,
        ``Sigma_p = cov_factor_ diag(cov_scale_[:, p]) cov_factor_'``.
    cov_factor_, cov_scale_ : (has_bias_ + R, has_bias_ + R) and (has_bias_ + R, P), that factorisation.
    beta_ : (P,) noise precisions; ``1 / sqrt(beta_)`` is the noise standard deviation per output.
    kernel_width_ : the width used.
    log_marginal_likelihood_ : (n_iter_ + 1,) log marginal likelihood, initially and after each iteration.
    n_iter_ : iterations run.
    n_candidates_ : training rows that carried a candidate Gaussian (all of them unless ``max_candidates``).
    converged_ : whether the convergence criterion was met before ``max_iter``.
    """

    def __init__(
        self,
        kernel_width="median",
        *,
        kernel: str = "rbf",
        bias: bool = True,
        max_iter: int = 10000,
        tol: float = 1e-3,
        tol_beta: float = 1e-6,
        beta_max: float = 1e6,
        beta_update_every: int = 10,
        alignment_max: float = 0.999,
        max_candidates: int | None = None,
        random_state=None,
    ):
        self.kernel = kernel
        self.kernel_width = kernel_width
        self.bias = bias
        self.max_iter = max_iter
        self.tol = tol
        self.tol_beta = tol_beta
        self.beta_max = beta_max
        self.beta_update_every = beta_update_every
        self.alignment_max = alignment_max
        self.max_candidates = max_candidates
        self.random_state = random_state

    def _check_params(self) -> None:
        if self.kernel != "rbf":
            raise VoxposeError(f"MVRVM: unknown kernel {self.kernel!r}; the only kernel is 'rbf'")
        if self.kernel_width != "median":
            positive_number(self.kernel_width, "MVRVM: kernel width")
        for name in ("max_iter", "beta_update_every"):
            integer(getattr(self, name), f"MVRVM: {name}")
        for name in ("tol", "tol_beta", "beta_max", "alignment_max"):
            positive_number(getattr(self, name), f"MVRVM: {name}")
        if self.max_candidates is not None:
            integer(self.max_candidates, "MVRVM: max_candidates")
        if self.alignment_max > 1:
            raise VoxposeError(f"MVRVM: alignment_max is a cosine, at most 1, got {self.alignment_max!r}")

    def fit(self, X, Y, start=None) -> "MVRVM":
        """Learn the sparse mapping from features ``X`` (N, d) to targets ``Y`` (N, P) or (N,); returns self.

        ``start``: ``(model, rows)``, an MVRVM of the same kernel width fitted on the rows ``rows`` of ``X``
        (e.g. the candidate of ``select_kernel_width``). Training then starts from its relevance vectors,
        precisions and noise instead of the empty model (``_warm_start``).
        """
        self._check_params()
        x = as_rows(X, "MVRVM: X")
        y_arr = np.asarray(Y, dtype=np.float64)
        self._single_output = y_arr.ndim == 1
        y = as_rows(y_arr[:, None] if self._single_output else y_arr, "MVRVM: Y")
        if y.shape[0] != x.shape[0]:
            raise VoxposeError(f"MVRVM: X has {x.shape[0]} rows but Y has {y.shape[0]}")
        if x.shape[0] < 2:
            raise VoxposeError(f"MVRVM: needs at least 2 training rows, got {x.shape[0]}")
        if self.kernel_width == "median":
            self.kernel_width_ = median_pairwise_distance(x, random_state=self.random_state)
        else:
            self.kernel_width_ = positive_number(self.kernel_width, "MVRVM: kernel width")
        self._centres = self._candidate_rows(x.shape[0], start)
        design = DesignStatistics(x, x[self._centres], self.kernel_width_, self.bias, y)
        var = y.var(axis=0)
        scale = np.where(var > 0, var, np.where(np.mean(y * y, axis=0) > 0, np.mean(y * y, axis=0), 1.0))
        cap = self.beta_max / scale
        post = Posterior(design, y, np.minimum(_SNR_INIT / scale, cap), self.alignment_max)
        lml, _ = post.refresh(update_beta=False, beta_cap=cap)
        if start is not None:
            lml = self._warm_start(post, *start, cap)
        elif self.bias:
            lml = self._bias_start(post, scale, cap)
        trace = [lml]
        self.converged_ = False
        next_check = _BETA_UPDATE_START  # next iteration at which the noise re-estimate is considered
        for it in range(1, self.max_iter + 1):
            move = self._best_move(post, exhaustive=False)
            if self._settled(move, post):
                move = self._best_move(post, exhaustive=True)
            if self._settled(move, post):
                # termination proposed: it stands unless the noise re-estimate changes beta
                if post.noise_change(cap) < self.tol_beta:
                    self.converged_ = True
                else:
                    lml, change = post.refresh(update_beta=True, beta_cap=cap)
                    self.converged_ = change < self.tol_beta
            else:
                j, alpha, gain = move
                if not np.isfinite(post.alpha[j]):
                    post.add(j, alpha)
                elif np.isfinite(alpha):
                    post.reestimate(j, alpha)
                else:
                    post.delete(j)
                lml += gain
                if (
                    it <= _BETA_UPDATE_START
                    or post.n_corrections > max(_MIN_CORRECTIONS, post.n_slots)
                    or post.degraded
                    or (it >= next_check and post.noise_change(cap) > self.tol)
                ):
                    lml, _ = post.refresh(update_beta=True, beta_cap=cap)
                if it >= next_check:
                    next_check = it + max(self.beta_update_every, post.n_slots // post.p)
            trace.append(lml)
            if it % 200 == 0:
                log.info("MVRVM iteration %d: %d basis functions, log ML %.6g", it, post.k, lml)
            if self.converged_:
                break
        if not self.converged_:
            warnings.warn(f"MVRVM: no convergence in {it} iterations (tol {self.tol:g})", ConvergenceWarning, 2)
        post.refresh(update_beta=False, beta_cap=cap)  # fold the rank-one terms into the final posterior
        self.n_iter_ = it
        self.log_marginal_likelihood_ = np.array(trace)
        self._store(post, x)
        log.info(
            "MVRVM: %s after %d iterations, %d of %d basis functions kept, log ML %.6g",
            "converged" if self.converged_ else "stopped",
            it,
            post.k,
            post.n_basis,
            lml,
        )
        return self

    def _candidate_rows(self, n: int, start) -> np.ndarray:
        """Sorted training rows that carry a candidate Gaussian: all ``n``, or ``max_candidates`` drawn at random
        (``random_state``) together with the relevance vectors of a warm ``start``."""
        if self.max_candidates is None or self.max_candidates >= n:
            return np.arange(n)
        drawn = np.random.default_rng(self.random_state).choice(n, size=self.max_candidates, replace=False)
        if start is not None:
            drawn = np.concatenate([drawn, np.asarray(start[1])[start[0].relevance_]])
        return np.unique(drawn)

    @staticmethod
    def _bias_start(post: Posterior, scale: np.ndarray, cap: np.ndarray) -> float:
        """Activate the bias alone; returns the log marginal likelihood.

        Its precision is its optimum, or, when that is infinite (targets centred on these rows, so that the
        bias alone explains nothing), ``1 / mean_p v_p``: a weight prior as wide as the targets. Why: with
        the bias active, every candidate's S and Q are those of its centred column, so the first Gaussians
        are chosen for how they vary over the rows, not for their level, which a wide Gaussian shares with
        every other. The bias is re-estimated and may be deleted like any other basis function later.
        """
        s, q = post.factors()
        alpha, _ = optimal_alpha(s[:1], q[:1] ** 2)
        post.add(0, float(alpha[0]) if np.isfinite(alpha[0]) else float(1.0 / np.mean(scale)))
        lml, _ = post.refresh(update_beta=False, beta_cap=cap)
        return lml

    def _warm_start(self, post: Posterior, model: "MVRVM", rows, cap: np.ndarray) -> float:
        """Activate ``model``'s basis functions (rows ``rows[model.relevance_]`` of this fit, and the bias if it
        kept one) at its precisions, with its noise; returns the log marginal likelihood.

        Why: a candidate fitted on many of the same rows is a nearby point of the same likelihood. It was
        introduced when cold fits could stall (with the uncentred alignment test, see ``Posterior``); measured
        then on the default run (fixed width, 2000 moves, cold start against this one):
        Figure 4's 600-d concatenated 2D shape contexts at width 0.41, the cold fit stopped after 5 moves
        with the bias alone (log ML -12967, the mean pose's 10.14 deg), the warm one kept 156 relevance
        vectors (-10390, 7.54 deg); where the cold fit does not stall it ends a little higher and the test
        error is the same (Table 1 MPPCA: -37586 cold, -37681 warm, 4.18 and 4.11 deg; Table 1 concatenated
        2D shape contexts: -33531, -33703, 3.62 and 3.63 deg), in the same time.
        """
        if model.kernel_width_ != self.kernel_width_ or model.coef_.shape[1] != post.p:
            raise VoxposeError("MVRVM: a warm start needs a model of the same kernel width and outputs")
        basis = np.searchsorted(self._centres, np.asarray(rows)[model.relevance_]) + int(self.bias)
        if model.has_bias_:
            basis = np.concatenate([[0], basis]) if self.bias else basis
        post.beta = np.minimum(model.beta_, cap)
        post.refresh(update_beta=False, beta_cap=cap)
        for j, alpha in zip(basis, model.alpha_[len(model.alpha_) - len(basis) :], strict=True):
            if np.isfinite(post.alpha[j]) or post.n_aligned[j]:
                continue  # collinear on these rows with one already active
            post.add(int(j), float(alpha))
        lml, _ = post.refresh(update_beta=False, beta_cap=cap)
        log.info("MVRVM: warm start from %d basis functions, log ML %.6g", post.k, lml)
        return lml

    def _settled(self, move, post: Posterior) -> bool:
        """Whether ``move`` proposes termination: none, or a re-estimate changing log alpha by < tol."""
        if move is None:
            return True
        j, new_alpha, _ = move
        return bool(np.isfinite(post.alpha[j]) and np.isfinite(new_alpha)) and bool(
            abs(np.log(new_alpha / post.alpha[j])) < self.tol
        )

    def _best_move(self, post: Posterior, exhaustive: bool):
        """The move with the largest gain in log ML, as ``(basis function, new alpha, gain)``, or None.

        Active basis functions are ranked by deletion and by two uphill Newton steps (``newton_ascent``)
        from the current alpha; the best-ranked re-estimate is then solved
        exactly (``optimal_alpha``, its global optimum). Inactive ones go through branch and bound: those
        whose ``series_bound`` beats the best gain so far get a feasible gain and a second upper bound
        from ``mode_bounds``, those whose bound still beats it a tighter one from a finer grid; only those
        whose bounds all beat it are solved exactly, in batches of decreasing bound. (Real Table 1 rows,
        12 outputs, 1335 candidates late in a fit: 125 bounds above the best gain from the modes alone,
        31 from the finer grid; an exact solve costs as much as the finer bound of 13 candidates.) With
        ``exhaustive``, every active function is solved exactly, every inactive one whose bounds beat the
        best addition or deletion too, and a re-estimate is returned only when no addition or deletion
        would raise the likelihood (SparseBayes's termination test).
        """
        s, q = post.factors()
        q2 = q * q
        alpha = post.alpha
        active = np.isfinite(alpha)
        usable = np.all((s > 0) & np.isfinite(s) & np.isfinite(q2), axis=1)
        act = np.flatnonzero(active & usable)
        current = np.zeros(post.n_basis)
        current[act] = contribution(alpha[act], s[act], q2[act])
        best = [None, _MIN_GAIN]
        structural = [None, _MIN_GAIN]  # best addition or deletion

        def offer(rows, new_alpha, value):
            """Moves of basis functions ``rows`` to ``new_alpha``, where l is ``value``."""
            # no "move" of an inactive function to infinity, and the last active one is never removed: a
            # re-estimate whose optimum is alpha = inf would be a deletion, which leaves the empty model
            removal = active[rows] & (post.k <= 1)
            gain = np.where(~np.isfinite(new_alpha) & (~active[rows] | removal), -np.inf, value - current[rows])
            c = int(np.argmax(gain))
            move = (int(rows[c]), float(new_alpha[c]), float(gain[c]))
            is_structural = not active[rows[c]] or not np.isfinite(new_alpha[c])
            for record, allowed in ((best, True), (structural, is_structural)):
                if allowed and move[2] > record[1]:
                    record[:] = [move, move[2]]

        pending = act[:0]  # active rows to solve exactly along with the first batch
        if act.size:
            if post.k > 1:
                offer(act, np.full(act.size, np.inf), np.zeros(act.size))  # deletion
            if exhaustive:
                pending = act
            else:
                offer(act, *newton_ascent(alpha[act], s[act], q2[act], _RANK_NEWTON))
                if best[0] is not None and active[best[0][0]] and np.isfinite(best[0][1]):
                    pending = np.array([best[0][0]])

        ina = np.flatnonzero(~active & usable & (post.n_aligned == 0))
        threshold = structural if exhaustive else best
        ina = ina[series_bound(s[ina], q2[ina]) > threshold[1]]
        order, upper = ina, np.zeros(0)
        if ina.size:
            mode_value, mode_alpha, upper = mode_bounds(s[ina], q2[ina])
            offer(ina, mode_alpha, mode_value)
            ina, upper = ina[upper > threshold[1]], upper[upper > threshold[1]]
        if ina.size:  # a finer grid for those left: tighter bounds, and fewer exact solves
            grid_value, grid_alpha, upper = mode_bounds(s[ina], q2[ina], _SUBDIVISIONS)
            offer(ina, grid_alpha, grid_value)
            rank = np.argsort(-upper, kind="stable")
            order, upper = ina[rank], upper[rank]
        start = 0
        while True:
            chunk = order[start : start + _BATCH][upper[start : start + _BATCH] > threshold[1]]
            rows = np.concatenate([pending, chunk])
            if not rows.size:
                break
            offer(rows, *optimal_alpha(s[rows], q2[rows]))
            pending, start = act[:0], start + _BATCH
            if chunk.size < _BATCH:
                break
        if exhaustive and structural[0] is not None and self._settled(best[0], post):
            return structural[0]
        return best[0]

    def _store(self, post: Posterior, x: np.ndarray) -> None:
        basis = post.active_basis  # after a refresh: slots 0..k-1, all live
        order = np.argsort(basis)
        basis = basis[order]
        self.has_bias_ = bool(self.bias and basis.size and basis[0] == 0)
        self.relevance_ = self._centres[basis[int(self.has_bias_) :] - int(self.bias)]
        self.relevance_vectors_ = x[self.relevance_]
        self.n_candidates_ = self._centres.size
        self.coef_ = post.mu[:, : basis.size][:, order].T.copy()
        self.alpha_ = post.alpha[basis]
        self.beta_ = post.beta.copy()
        self.cov_factor_ = post.w[order]
        self.cov_scale_ = post.c

    def to_arrays(self) -> tuple[dict, dict]:
        """The fitted model as (arrays, meta); ``from_arrays`` inverts it.

        ``coef`` is (K,) after a fit on 1-D targets, so that the restored model predicts the same shapes;
        ``cov_factor`` and ``cov_scale`` (when the model has them) serve ``predict(return_std=True)``.
        """
        check_fitted(self, "coef_")
        arrays = {"relevance": self.relevance_, "relevance_vectors": self.relevance_vectors_,
                  "coef": self.coef_[:, 0] if self._single_output else self.coef_, "alpha": self.alpha_,
                  "beta": self.beta_}  # fmt: skip
        if hasattr(self, "cov_factor_"):
            arrays |= {"cov_factor": self.cov_factor_, "cov_scale": self.cov_scale_}
        meta = {"kernel_width": self.kernel_width_, "has_bias": self.has_bias_,
                "log_marginal_likelihood": list(map(float, self.log_marginal_likelihood_))}  # fmt: skip
        return arrays, meta

    @classmethod
    def from_arrays(cls, arrays: dict, meta: dict) -> "MVRVM":
        """The MVRVM that ``to_arrays`` recorded, fitted: it predicts as the original did.

        Without ``cov_factor`` and ``cov_scale`` (a regressor file keeps the posterior mean only,
        ``voxpose.regression.stored``) it predicts means, and ``return_std`` or ``sigma_`` raise.
        Of the fit record only the likelihood trace is kept (empty when ``meta`` lacks it), not ``n_iter_``
        or ``converged_``.
        """
        model = cls(float(meta["kernel_width"]))
        coef = np.asarray(arrays["coef"])
        model._single_output = coef.ndim == 1
        model.coef_ = coef[:, None] if model._single_output else coef
        model.relevance_, model.relevance_vectors_ = arrays["relevance"], arrays["relevance_vectors"]
        model.alpha_, model.beta_ = arrays["alpha"], arrays["beta"]
        model.kernel_width_, model.has_bias_ = float(meta["kernel_width"]), bool(meta["has_bias"])
        model.log_marginal_likelihood_ = np.asarray(meta.get("log_marginal_likelihood", []), dtype=np.float64)
        if "cov_factor" in arrays:
            model.cov_factor_, model.cov_scale_ = arrays["cov_factor"], arrays["cov_scale"]
        return model

    def _covariance(self) -> tuple[np.ndarray, np.ndarray]:
        """``cov_factor_`` and ``cov_scale_``, or an error saying why they are missing."""
        check_fitted(self, "coef_")
        if not hasattr(self, "cov_factor_"):
            raise VoxposeError(
                "MVRVM: restored without its posterior covariance (regressor files keep the mean only): "
                "no return_std or sigma_"
            )
        return self.cov_factor_, self.cov_scale_

    @property
    def sigma_(self) -> np.ndarray:
        """(P, K, K) posterior weight covariance per output, rows in ``coef_`` order."""
        factor, scale = self._covariance()
        return np.stack([(factor * c) @ factor.T for c in scale.T])

    def _basis(self, X) -> np.ndarray:
        check_fitted(self, "coef_")
        x = as_rows(X, "MVRVM: X", self.relevance_vectors_.shape[1])
        return design_matrix(x, self.relevance_vectors_, self.kernel_width_, self.has_bias_)

    def predict(self, X, return_std: bool = False):
        """Posterior mean (n, P) (or (n,) after a 1-D fit) for inputs ``X`` (n, d).

        With ``return_std``, also the predictive standard deviation ``sqrt(1/beta_p + phi' Sigma_p phi)``
        of each output, same shape.
        """
        phi = self._basis(X)
        mean = phi @ self.coef_
        if not return_std:
            return mean[:, 0] if self._single_output else mean
        factor, scale = self._covariance()
        proj = phi @ factor
        std = np.sqrt(1.0 / self.beta_ + (proj * proj) @ scale)
        return (mean[:, 0], std[:, 0]) if self._single_output else (mean, std)


def select_kernel_width(
    X,
    Y,
    widths=None,
    scales=(0.25, 0.5, 1.0, 2.0, 4.0),
    groups=None,
    validation_fraction: float = 0.2,
    random_state=None,
    max_rows: int | None = None,
    **params,
) -> tuple[float, list[dict], tuple[MVRVM, np.ndarray]]:
    """Choose the MVRVM kernel width on held-out *training* rows (the caller passes training data only).

    Rule: hold out rows with ``voxpose.regression.kernels.holdout_split`` (whole ``groups``, e.g. motions, when
    given); try ``widths``, or ``scales`` times the median pairwise distance of the fitting rows; fit an
    ``MVRVM(kernel_width=w, **params)`` on the fitting rows for each; keep the width with the lowest
    validation RMSE, ``sqrt(mean over rows of ||y - y_hat||^2)`` (for PCA pose coordinates this is the
    RMS angle-vector error of the reconstructed poses, since the components are orthonormal); ties go
    to the smaller width. Refit on all training rows with the chosen width afterwards, from ``start``.

    With more than ``max_rows`` rows, all of this happens on ``max_rows`` of them drawn at random (seeded by
    ``random_state``; ``voxpose.regression.kernels.selection_split``), exactly as if only those had been passed:
    the widths are only ranked, and the selection's fits would otherwise cost as much as the final one for every
    width (None: every row).

    Returns
    -------
    width : the chosen kernel width.
    table : one record (dict) per width, in the order tried: ``scale`` (NaN for explicit widths), ``width``,
        ``val_rmse``, ``n_relevance``, ``n_iter``, ``converged``. Plain records, not a DataFrame: a regress job
        would otherwise import pandas (0.15 s) for three rows.
    start : ``(model, fit_rows)``, the chosen candidate and the rows it was fitted on, for ``MVRVM.fit``.
    """
    x = as_rows(X, "kernel width selection: X")
    y = np.asarray(Y, dtype=np.float64)
    y = as_rows(y[:, None] if y.ndim == 1 else y, "kernel width selection: Y")
    if x.shape[0] != y.shape[0]:
        raise VoxposeError(f"kernel width selection: X has {x.shape[0]} rows but Y has {y.shape[0]}")
    fit_rows, val_rows = selection_split(x.shape[0], max_rows, validation_fraction, groups, random_state,
                                         "kernel width selection")  # fmt: skip
    if widths is None:
        base = median_pairwise_distance(x[fit_rows], random_state=random_state)
        scale_list = [float(s) for s in scales]
        width_list = [positive_number(s * base, "kernel width selection: width") for s in scale_list]
    else:
        width_list = [positive_number(w, "kernel width selection: width") for w in np.atleast_1d(widths)]
        scale_list = [float("nan")] * len(width_list)
    if not width_list:
        raise VoxposeError("kernel width selection: no widths to try")
    rows, models = [], []
    for scale, width in zip(scale_list, width_list, strict=True):
        model = MVRVM(kernel_width=width, random_state=random_state, **params).fit(x[fit_rows], y[fit_rows])
        models.append(model)
        err = model.predict(x[val_rows]) - y[val_rows]
        rmse = float(np.sqrt(np.mean(np.sum(err * err, axis=1))))
        log.info("kernel width %.4g: validation RMSE %.4g, %d relevance vectors", width, rmse, len(model.relevance_))
        rows.append(
            {
                "scale": scale,
                "width": float(width),
                "val_rmse": rmse,
                "n_relevance": len(model.relevance_),
                "n_iter": int(model.n_iter_),
                "converged": bool(model.converged_),
            }
        )
    best = _best_width(rows)
    return float(rows[best]["width"]), rows, (models[best], fit_rows)


def _best_width(rows: list[dict]) -> int:
    """Index of the record with the lowest ``val_rmse``; ties go to the smaller ``width``, then to the earlier
    record, and a NaN RMSE never wins (unless every one is NaN)."""
    return min(range(len(rows)), key=lambda i: (np.isnan(rows[i]["val_rmse"]), np.nan_to_num(rows[i]["val_rmse"]),
                                                rows[i]["width"], i))  # fmt: skip
