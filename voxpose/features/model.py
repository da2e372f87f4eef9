"""The feature transformation of Section 5 as a stored model: fit on training descriptors, save, load, apply.

Two methods share the interface: ``mppca`` (Mixture of PPCA, Eq. 5 features) and ``kmeans`` (the K-means
soft-vote histogram of Table 1's third row). Both are fitted on a seeded subsample of the experiment's
training descriptors (``fit_subsample`` rows; all rows when it is null or larger than the set); the sizes
used are recorded in the model file.
"""

import logging

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.features.fit_keys import FIT_KEYS
from voxpose.features.frame import SoftVoteRule, kmeans_features, mppca_features
from voxpose.features.heading_sense import SENSES, choose_senses
from voxpose.features.kmeans import KMeans, nearest_centres
from voxpose.features.mppca import MPPCA
from voxpose.features.novelty import NoveltyRange, frame_scores
from voxpose.io.hdf5 import read_arrays, write_arrays

log = logging.getLogger(__name__)

METHODS = tuple(FIT_KEYS)


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
                random_state=seed,
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

    def transform(self, descriptors: np.ndarray, frame_index: np.ndarray, n_frames: int):
        """-> (features (n_frames, K), counts (n_frames,)); frames without descriptors get NaN rows."""
        if self.method == "mppca":
            return mppca_features(self.estimator, descriptors, frame_index, n_frames)
        return kmeans_features(self.estimator.cluster_centers_, descriptors, frame_index, n_frames, rule=self.rule)

    def transform_frames(self, descriptors: list) -> tuple[np.ndarray, np.ndarray]:
        """``transform`` of a list with each frame's (B_f, bins) descriptors (empty for gaps)."""
        frame_index = np.repeat(np.arange(len(descriptors)), [len(d) for d in descriptors])
        return self.transform(np.concatenate(descriptors), frame_index, len(descriptors))

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

    def save(self, path) -> None:
        write_arrays(path, "feature-model", *self.to_arrays())

    @classmethod
    def load(cls, path) -> "FeatureModel":
        return cls.from_arrays(*read_arrays(path, "feature-model"))
