"""The feature transformation of Section 5 as a stored model: fit on training descriptors, save, load, apply.

Two methods share the interface: ``mppca`` (Mixture of PPCA, Eq. 5 features) and ``kmeans`` (the K-means
soft-vote histogram of Table 1's third row). Both are fitted on a seeded subsample of the experiment's
training descriptors (``fit_subsample`` rows; all rows when it is null or larger than the set); the sizes
used are recorded in the model file.
"""

import logging
from typing import NamedTuple

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.features.fit_keys import FIT_KEYS
from voxpose.features.frame import SoftVoteRule, kmeans_features, mppca_features
from voxpose.features.heading_sense import SENSE_DESCRIPTORS, SENSES, choose_senses, true_turns
from voxpose.features.kmeans import KMeans, nearest_centres
from voxpose.features.mppca import MPPCA
from voxpose.features.novelty import DESCRIPTORS_PER_FRAME, NoveltyRange, frame_means, frame_scores
from voxpose.io.hdf5 import read_arrays, write_arrays

log = logging.getLogger(__name__)

METHODS = tuple(FIT_KEYS)


def _frame_index(frames: list) -> np.ndarray:
    """(N,) the frame of each row of ``np.concatenate(frames)``."""
    return np.repeat(np.arange(len(frames)), [len(d) for d in frames])


def _per_frame(values: np.ndarray, counts: np.ndarray) -> list:
    """``values`` (N,) of concatenated frames split back into the frames (``counts`` rows each)."""
    return np.split(values, np.cumsum(counts)[:-1])


class FrameFeatures(NamedTuple):
    """A sequence's frames oriented and featurised (``FeatureModel.frame_features``)."""

    frames: list  # (B_f, bins) descriptors, turned about where the senses were chosen so
    h0: np.ndarray | None  # (F,) reference headings with the chosen senses; None in the world frame
    features: np.ndarray  # (F, K), NaN rows at gaps
    counts: np.ndarray  # (F,) descriptors per frame
    scores: np.ndarray | None  # (F,) novelty scores; None for a model without a novelty range
    novelty: dict | None  # the sequence's novelty summary (``NoveltyRange.check``)

    def heading_offsets(self) -> np.ndarray:
        """(F,) the headings the regressor's estimates are relative to: ``h0``, or 0 in the world frame."""
        return np.zeros(len(self.counts)) if self.h0 is None else self.h0


def subsample_indices(n_rows: int, n: int | None, seed: int) -> np.ndarray:
    """Sorted indices of ``n`` of ``n_rows`` rows drawn without replacement (seeded); all if ``n`` is None."""
    if n is None or n >= n_rows:
        return np.arange(n_rows)
    rng = np.random.default_rng([seed, 5])
    return np.sort(rng.choice(n_rows, size=n, replace=False))


def subsample(descriptors: np.ndarray, n: int | None, seed: int) -> np.ndarray:
    """``n`` rows drawn without replacement (seeded), in their original order; all rows if ``n`` is None."""
    if n is None or n >= len(descriptors):
        return descriptors
    return descriptors[subsample_indices(len(descriptors), n, seed)]


class FeatureModel:
    """A fitted MPPCA or K-means transformation; ``transform`` gives one feature vector per frame."""

    def __init__(self, method: str, estimator, rule: SoftVoteRule | None, meta: dict):
        self.method, self.estimator, self.rule, self.meta = method, estimator, rule, meta

    @classmethod
    def fit(cls, method: str, descriptors: np.ndarray, cfg: dict, seed: int) -> "FeatureModel":
        """Fit on the rows of ``descriptors`` (N, d) with the config's ``features`` section ``cfg``."""
        rows = subsample(descriptors, cfg.get("fit_subsample"), seed)
        return cls.fit_rows(method, rows, len(descriptors), cfg, seed)

    @classmethod
    def fit_rows(cls, method: str, rows: np.ndarray, n_train: int, cfg: dict, seed: int) -> "FeatureModel":
        """Fit on ``rows`` already drawn from a training set of ``n_train`` descriptors (``training_set``)."""
        if method not in METHODS:
            raise VoxposeError(f"unknown feature method {method!r}: expected one of {', '.join(METHODS)}")
        log.info(
            "%s: fitting K=%d on %d of %d descriptors",
            method,
            cfg["n_components"],
            len(rows),
            n_train,
        )
        meta = {
            "method": method,
            "params": cfg,
            "seed": seed,
            "n_fit": len(rows),
            "n_train": n_train,
        }
        if method == "mppca":
            model = MPPCA(
                cfg["n_components"], n_latent=cfg["n_latent"], max_iter=cfg["max_iter"], tol=cfg["tol"],
                random_state=seed, compiled=True,  # EM evaluates every row each iteration: the kernel repays
            ).fit(rows)  # fmt: skip
            rule = None
        else:
            model = KMeans(cfg["n_components"], max_iter=cfg["max_iter"], random_state=seed).fit(rows)
            rule = SoftVoteRule.from_training(model.cluster_centers_, rows, n_nearest=cfg["kmeans_neighbours"])
        return cls(method, model, rule, meta | model.to_arrays()[1])

    def with_novelty_range(self, frames: list) -> "FeatureModel":
        """Record the training frames' novelty range (MPPCA only: K-means has no density); ``frames`` is the
        list of the training frames' (B_f, bins) descriptors (features/novelty.py)."""
        if self.method == "mppca":
            self.meta = self.meta | {"novelty": NoveltyRange.from_training(self.estimator, frames).to_dict()}
        return self

    def novelty(self, motion: str, frames: list) -> tuple[np.ndarray | None, dict | None]:
        """(per-frame novelty scores, the motion's summary) against the training range, logging a warning
        when the motion lies outside it; (None, None) for a model without a range."""
        if "novelty" not in self.meta:
            return None, None
        scores = frame_scores(self.estimator, frames)
        return scores, NoveltyRange(**self.meta["novelty"]).check(motion, scores)

    @property
    def heading_sense(self) -> str:
        """How body-frame senses are chosen: the config's ``features.heading_sense`` (``density`` or ``shape``,
        ``voxpose.features.heading_sense``); ``shape`` for models fitted before the key existed, as they were."""
        sense = self.meta.get("params", {}).get("heading_sense", "shape")
        if sense not in SENSES:
            raise VoxposeError(f"features.heading_sense must be one of {', '.join(SENSES)}, got {sense!r}")
        return sense

    def log_density(self, rows: np.ndarray) -> np.ndarray:
        """(n,) log density of descriptors (n, bins), up to a constant: the MPPCA's ``log p(t)``; for K-means
        the isotropic mixture its soft vote assumes, ``-min_j |t - c_j|^2 / (2 s^2)`` (``s``: the vote's width)."""
        if self.method == "mppca":
            return self.estimator.score_samples(rows)
        return -nearest_centres(rows, self.estimator.cluster_centers_)[1] / (2.0 * self.rule.bandwidth**2)

    def orient(self, frames: list, h0, n_a: int, name: str = "motion") -> tuple[list, np.ndarray | None]:
        """``(frames, h0)`` with body-frame senses chosen by this model's density when it was fitted with
        ``heading_sense: density``; unchanged otherwise and in the world frame (``h0`` None)."""
        if h0 is None or self.heading_sense != "density":
            return frames, h0
        return choose_senses(self.log_density, frames, h0, n_a, name)

    def frame_features(self, frames: list, h0, n_a: int, name: str = "motion") -> FrameFeatures:
        """``orient``, ``transform_frames`` and ``novelty`` of one sequence of frames (each (B_f, bins)), the
        mixture evaluated once per descriptor where it can be.

        With an MPPCA choosing the senses by its density, the posteriors of Eq. 5 and the log densities of the
        sense evidence and the novelty score come from the same log joint: every descriptor is evaluated as it
        stands (posterior and density together), the evidence's turned descriptors on their own, and only the
        frames then turned about once more. Otherwise the three run one after the other. Either way the result
        is theirs (``tests/features/test_heading_sense.py``); the fused path evaluates 240 rather than 300 descriptors
        per frame at the default settings (200 basis voxels, 40 for the sense, 20 for the novelty).
        """
        if self.method != "mppca" or h0 is None or self.heading_sense != "density":
            frames, h0 = self.orient(frames, h0, n_a, name)
            features, counts = self.transform_frames(frames)
            return FrameFeatures(frames, h0, features, counts, *self.novelty(name, frames))
        features, counts, density = self._features_and_density(frames)
        density = _per_frame(density, counts)
        as_is = frame_means(np.asarray, density, SENSE_DESCRIPTORS)
        oriented, chosen = choose_senses(self.log_density, frames, h0, n_a, name, as_is=as_is)
        turned = np.flatnonzero(true_turns(h0, chosen) & (counts > 0))
        if turned.size:
            features[turned], _, again = self._features_and_density([oriented[f] for f in turned])
            for f, d in zip(turned, _per_frame(again, counts[turned]), strict=True):
                density[f] = d
        scores, summary = None, None
        if "novelty" in self.meta:
            scores = frame_means(np.asarray, density, DESCRIPTORS_PER_FRAME)
            summary = NoveltyRange(**self.meta["novelty"]).check(name, scores)
        return FrameFeatures(oriented, chosen, features, counts, scores, summary)

    def _features_and_density(self, frames: list) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(features (F, K), counts (F,), log densities of every descriptor (N,)) of an MPPCA model."""
        return mppca_features(self.estimator, np.concatenate(frames), _frame_index(frames), len(frames), density=True)

    def transform(self, descriptors: np.ndarray, frame_index: np.ndarray, n_frames: int):
        """-> (features (n_frames, K), counts (n_frames,)); frames without descriptors get NaN rows."""
        if self.method == "mppca":
            return mppca_features(self.estimator, descriptors, frame_index, n_frames)
        return kmeans_features(self.estimator.cluster_centers_, descriptors, frame_index, n_frames, rule=self.rule)

    def transform_frames(self, descriptors: list) -> tuple[np.ndarray, np.ndarray]:
        """``transform`` of a list with each frame's (B_f, bins) descriptors (empty for gaps)."""
        return self.transform(np.concatenate(descriptors), _frame_index(descriptors), len(descriptors))

    def to_arrays(self) -> tuple[dict, dict]:
        """(arrays, meta) that ``from_arrays`` turns back into this model (the model file's contents): the
        estimator's arrays, and ``meta`` (the estimator's fit record among it) with the soft-vote rule."""
        rule = {} if self.rule is None else {"n_nearest": self.rule.n_nearest, "bandwidth": self.rule.bandwidth}
        return self.estimator.to_arrays()[0], self.meta | rule

    @classmethod
    def from_arrays(cls, arrays: dict, meta: dict) -> "FeatureModel":
        method = meta["method"]
        if method == "mppca":
            return cls(method, MPPCA.from_arrays(arrays, meta), None, meta)
        return cls(method, KMeans.from_arrays(arrays, meta), SoftVoteRule(meta["n_nearest"], meta["bandwidth"]), meta)

    def compiled(self) -> "FeatureModel":
        """This model with an MPPCA's scoring on its compiled, screened path (``MPPCA.compiled``): for processes
        that evaluate many frames (``voxpose features``, ``voxpose predict``); the numbers are the numpy path's to
        rounding and 1e-30. K-means is unchanged."""
        if self.method == "mppca":
            self.estimator.compiled = True
        return self

    def save(self, path) -> None:
        write_arrays(path, "feature-model", *self.to_arrays())

    @classmethod
    def load(cls, path) -> "FeatureModel":
        return cls.from_arrays(*read_arrays(path, "feature-model"))
