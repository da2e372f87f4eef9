"""One experiment's regression (Sections 2, 3, 6): pose PCA, kernel width, MVRVM, baselines, predictions, errors.

With body-frame descriptors every method regresses the heading relative to each frame's reference heading
(``voxpose.descriptors.body_frame``), which is added back to its estimates. Training rows are the frames of the
training motions that have a feature vector (frames with an empty hull are gaps and are skipped); test frames with a
gap get no prediction (NaN) and are left out of the errors, which are reported with the number of frames they cover.
The MVRVM regresses the M-dimensional PCA pose coordinates (Eq. 1) of the encoded pose
(``voxpose.regression.pose_encoding``: the body heading as a point on a circle by default) and predictions are
mapped back to the 42 angles, where Eq. 6 is evaluated. The kernel width is chosen on held-out training motions
(whole motions held out), never on test motions.

Reference baselines in the same evaluation show what the sparse Bayesian regressor buys: the mean training
pose, the nearest training frame in feature space, and kernel ridge regression with the MVRVM's kernel, its
ridge chosen on held-out training motions as the width is (random held-out rows, the earlier rule, sit next to
frames of the same motion and favour small ridges: refitted on the nine real subject-held-out training sets of
the c13a236 run, with its features, widths and rows, the motion rule gave full-body errors 0.00-0.18 deg lower
on the held-out performers, none higher).
"""

import json
import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from voxpose.errors import VoxposeError
from voxpose.evaluation import metrics
from voxpose.io.atomic import atomic_path
from voxpose.io.hdf5 import read_arrays, read_groups, write_arrays, write_groups
from voxpose.motion import canon
from voxpose.regression import pose_encoding
from voxpose.regression.baselines import KernelRidge, MeanPose, NearestNeighbour
from voxpose.regression.mvrvm import MVRVM, select_kernel_width
from voxpose.regression.pose_space import PosePCA
from voxpose.regression.stored import regressor_arrays, regressor_from_arrays

log = logging.getLogger(__name__)


def thin_frames(valid: list, max_frames: int | None) -> list:
    """Keep every s-th valid frame of each motion, with the smallest stride s that leaves at most
    ``max_frames`` in all (None or enough room: all of them). Even strides in time keep every motion and
    its headings represented; the MVRVM's cost grows with the square of the training rows, and the paper
    trains on 1744 frames (Table 2), where a real motion library has several thousand."""
    total = int(sum(int(v.sum()) for v in valid))
    if max_frames is None or total <= max_frames:
        return valid
    if max_frames < sum(bool(v.any()) for v in valid):
        raise VoxposeError(f"config key regression.max_train_frames: {max_frames} is fewer than the training motions")
    stride = 1
    while sum(int(np.ceil(v.sum() / stride)) for v in valid) > max_frames:
        stride += 1
    out = []
    for v in valid:
        keep = np.zeros_like(v)
        keep[np.flatnonzero(v)[::stride]] = True
        out.append(keep)
    return out


def reference_heading(entry: dict) -> np.ndarray:
    """(F,) a motion's reference headings in degrees: those of body-frame descriptors (the regressor learns the
    heading relative to them, ``voxpose.descriptors.body_frame``), zeros in the world frame."""
    h0 = entry.get("reference_heading")
    return np.zeros(len(entry["counts"])) if h0 is None else np.asarray(h0, dtype=float)


def _rows(features: dict, motions: dict, names, max_frames: int | None = None):
    xs, ys, groups = [], [], []
    for name in names:
        if name not in features:
            raise VoxposeError(f"no features for motion {name!r}")
    masks = thin_frames([features[name]["counts"] > 0 for name in names], max_frames)
    for g, (name, valid) in enumerate(zip(names, masks, strict=True)):
        xs.append(features[name]["features"][valid])
        ys.append(pose_encoding.turn_heading(motions[name].angles[valid], -reference_heading(features[name])[valid]))
        groups.append(np.full(int(valid.sum()), g))
    return np.concatenate(xs), np.concatenate(ys), np.concatenate(groups)


def _errors(true, pred, offsets_per_frame, kinds) -> dict:
    """Table columns, per joint, per angle and per motion type for one method over valid test frames."""
    out = metrics.table_errors(true, pred)
    out["left_shoulder"], out["right_hip"] = out.pop("lshoulder"), out.pop("rhip")
    out["left_shoulder_mean"], out["right_hip_mean"] = out.pop("lshoulder_mean"), out.pop("rhip_mean")
    position = np.concatenate([metrics.position_errors_mm(true[idx], pred[idx], off) for off, idx in offsets_per_frame])
    out["position_mm"] = float(position.mean())
    out["per_joint"] = dict(zip(canon.JOINTS, metrics.per_joint_error(true, pred).tolist(), strict=True))
    out["per_angle"] = dict(zip(canon.ANGLE_NAMES, metrics.per_angle_error(true, pred).tolist(), strict=True))
    out["heading_by_bin"] = metrics.heading_by_bin(true, pred)
    out["per_kind"] = {
        kind: {
            "full_body": metrics.full_body_error(true[kinds == kind], pred[kinds == kind]),
            "frames": int((kinds == kind).sum()),
        }  # fmt: skip
        for kind in sorted(set(kinds))
    }
    return out


def evaluate(predict: dict, features: dict, motions: dict, test: list):
    """Predictions and errors of each method on the ``test`` motions' frames that have features.

    ``predict``: method -> function from features (n, K) to the 42 angles (n, 42). Returns
    (predictions: motion -> {"true", "valid", "offsets", "root_positions", "pred_<method>",
    "frame_error_<method>"}, {"test_frames", "test_gaps", "methods": method -> errors}).
    """
    predictions, true_all, pred_all, kinds, spans = {}, [], {m: [] for m in predict}, [], []
    start = 0
    for name in test:
        if name not in features:
            raise VoxposeError(f"no features for motion {name!r}")
        motion = motions[name]
        valid = features[name]["counts"] > 0
        x = features[name]["features"][valid]
        h0 = reference_heading(features[name])[valid]
        entry = {"true": motion.angles, "valid": valid, "offsets": motion.offsets,
                 "root_positions": motion.positions[:, 0]}  # fmt: skip
        for method, fn in predict.items():
            pred = pose_encoding.turn_heading(fn(x), h0)
            full = np.full_like(motion.angles, np.nan)
            full[valid] = pred
            entry[f"pred_{method}"] = full
            err = np.full(motion.n_frames, np.nan)
            err[valid] = metrics.frame_errors(motion.angles[valid], pred)
            entry[f"frame_error_{method}"] = err
            pred_all[method].append(pred)
        predictions[name] = entry
        true_all.append(motion.angles[valid])
        kinds += [motion.kind] * int(valid.sum())
        spans.append((motion.offsets, np.arange(start, start + int(valid.sum()))))
        start += int(valid.sum())
    true = np.concatenate(true_all)
    kinds = np.array(kinds)
    return predictions, {
        "test_frames": len(true),
        "test_gaps": int(sum((~p["valid"]).sum() for p in predictions.values())),
        "methods": {m: _errors(true, np.concatenate(pred_all[m]), spans, kinds) for m in predict},
    }


@dataclass
class Fit:
    """A regressor fitted on one training set: pose PCA, MVRVM, the baselines and what the fit measured.

    One fit serves every test set of every experiment with the same training motions and settings
    (``test``); ``save``/``load`` keep it in three files: the regressor (``voxpose.regression.stored``, the
    layout the model file and the claims also read), the baselines and the fit's summary (JSON).
    """

    pca: PosePCA
    mvrvm: MVRVM
    heading: str
    summary: dict
    baselines: dict = field(default_factory=dict)  # name -> fitted baseline; empty: the PCA mean stands in

    def predictors(self) -> dict:
        """Method -> function from features (n, K) to the 42 angles (n, 42): the MVRVM and the baselines."""
        pca, heading = self.pca, self.heading
        out = {"mvrvm": _in_pose_space(pca, self.mvrvm, heading)}
        if not self.baselines:  # a regressor without its baselines: the mean pose is the PCA mean
            out["mean_pose"] = lambda x: pose_encoding.decode(np.broadcast_to(pca.mean_, (len(x), pca.mean_.size)),
                                                              heading)  # fmt: skip
            return out
        for name, model in self.baselines.items():
            if name == "kernel_ridge":  # regresses the pose-PCA coordinates, as the MVRVM does
                out[name] = _in_pose_space(pca, model, heading)
            else:
                out[name] = lambda x, model=model: pose_encoding.decode(model.predict(x), heading)
        return out

    def test(self, features: dict, motions: dict, test: list) -> tuple[dict, dict]:
        """Predictions and errors of every method on the ``test`` motions (``evaluate``); the summary also
        holds the fit's own (training frames, M, relevance vectors, kernel width, convergence)."""
        predictions, test_summary = evaluate(self.predictors(), features, motions, test)
        summary = self.summary | {"test": test} | test_summary
        for m, e in summary["methods"].items():
            log.info("%s: full body %.2f deg, heading %.2f, left shoulder %.2f, right hip %.2f, %.0f mm", m,
                     e["full_body"], e["heading"], e["left_shoulder"], e["right_hip"], e["position_mm"])  # fmt: skip
        return predictions, summary

    def save(self, regressor, baselines, summary) -> None:
        """Write the regressor, the baselines and the fit's summary, each atomically."""
        write_arrays(regressor, "regressor", *regressor_arrays(self.pca, self.mvrvm))
        groups = {name: model.to_arrays() for name, model in self.baselines.items()}
        write_groups(baselines, "baselines", groups, {})
        with atomic_path(summary) as tmp:
            tmp.write_text(json.dumps(self.summary | {"heading": self.heading}, indent=1))

    @classmethod
    def load(cls, regressor, baselines=None, summary=None, heading: str | None = None) -> "Fit":
        """A saved fit; without ``baselines`` only the MVRVM and the PCA-mean pose predict (a regressor
        file alone, as the model file holds it). The heading encoding is the fit summary's, else ``heading``."""
        pca, mvrvm = regressor_from_arrays(*read_arrays(regressor, "regressor"))
        fit_summary = json.loads(Path(summary).read_text()) if summary else {}
        heading = fit_summary.pop("heading", heading)
        if heading is None:
            raise VoxposeError(f"{regressor}: the heading encoding is unknown (give the fit's summary)")
        models = {}
        if baselines:
            groups, _ = read_groups(baselines, "baselines")
            models = {name: cls_.from_arrays(*groups[name]) for name, cls_ in BASELINES.items() if name in groups}
        return cls(pca, mvrvm, heading, fit_summary, models)


BASELINES = {"mean_pose": MeanPose, "nearest_neighbour": NearestNeighbour, "kernel_ridge": KernelRidge}


def fit_mvrvm(x: np.ndarray, z: np.ndarray, groups: np.ndarray, cfg: dict, seed: int):
    """The MVRVM of the config's ``regression`` section ``cfg`` fitted on features ``x`` to pose-PCA coordinates
    ``z``, its width chosen on held-out ``groups`` (motions) when ``auto``; returns (model, width table or None)."""
    params = {"max_iter": cfg["max_iter"], "tol": cfg["tol"], "max_candidates": cfg.get("max_candidates")}
    width_table = start = None
    width = cfg["kernel_width"]
    if width == "auto":
        # the candidate widths are only ranked, so their fits get a smaller budget (and at most
        # selection_max_rows rows) than the final fit, which starts from the chosen candidate (MVRVM._warm_start)
        budget = min(cfg["max_iter"], cfg.get("selection_max_iter") or cfg["max_iter"])
        width, width_table, start = select_kernel_width(x, z, scales=cfg["width_scales"], groups=groups,
                                                        random_state=seed, max_rows=cfg.get("selection_max_rows"),
                                                        **params | {"max_iter": budget})  # fmt: skip
    return MVRVM(kernel_width=width, random_state=seed, **params).fit(x, z, start=start), width_table


def fit(features: dict, motions: dict, train: list, cfg: dict, seed: int) -> Fit:
    """Fit the pose PCA (Eq. 1), the MVRVM (Section 3, kernel width chosen on held-out training motions) and
    the baselines on the ``train`` motions' frames that have features.

    ``features``: motion -> {"features": (F, K), "counts": (F,)}; ``motions``: motion -> MotionData;
    ``cfg``: the config's ``regression`` section.
    """
    x_train, angles_train, groups = _rows(features, motions, train, cfg.get("max_train_frames"))
    heading = cfg.get("heading", "vector")
    y_train = pose_encoding.encode(angles_train, heading)
    log.info(
        "regression: %d training frames from %d motions, %d features",
        len(x_train),
        len(train),
        x_train.shape[1],
    )
    pca = PosePCA(variance=cfg["pca_variance"]).fit(y_train)
    z_train = pca.transform(y_train)
    log.info("pose PCA: M = %d components keep %.1f %% of the variance (Eq. 1)", pca.n_components_,
             100 * pca.explained_variance_ratio_.sum())  # fmt: skip
    model, width_table = fit_mvrvm(x_train, z_train, groups, cfg, seed)
    log.info("MVRVM: kernel width %.4g, %d of %d relevance vectors, converged %s after %d iterations",
             model.kernel_width_, len(model.relevance_), len(x_train), model.converged_, model.n_iter_)  # fmt: skip
    baselines = {
        "mean_pose": MeanPose().fit(x_train, y_train),
        "nearest_neighbour": NearestNeighbour().fit(x_train, y_train),
        "kernel_ridge": KernelRidge(kernel_width=model.kernel_width_, max_rows=cfg.get("selection_max_rows"),
                                    random_state=seed).fit(x_train, z_train, groups=groups),  # fmt: skip
    }

    summary = {
        "train": train,
        "train_frames": len(x_train),
        "pose_dims": int(pca.n_components_),
        "pose_variance": float(pca.explained_variance_ratio_.sum()),
        "n_relevance": len(model.relevance_),
        "kernel_width": float(model.kernel_width_),
        "width_selection": width_table,
        "mvrvm": {
            "n_iter": int(model.n_iter_),
            "converged": bool(model.converged_),
            "candidates": int(model.n_candidates_),
            "noise_std": (1 / np.sqrt(model.beta_)).tolist(),
        },  # fmt: skip
    }
    return Fit(pca, model, heading, summary, baselines)


def _in_pose_space(pca: PosePCA, regressor, heading: str):
    """Features -> the 42 angles through a regressor of pose-PCA coordinates (Eq. 1) and the heading code."""
    return lambda x: pose_encoding.decode(pca.inverse_transform(regressor.predict(x)), heading)
