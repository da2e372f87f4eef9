"""Subcommands measuring the paper's claims (issue 8): camera-setup independence, robustness to degraded
silhouettes, and the Agarwal & Triggs baseline computed instead of quoted. Same shape as ``voxpose.cli.pipeline``.
"""

import json
import logging

from voxpose.cli.pipeline import _out, _params

log = logging.getLogger("voxpose")


def _voxelize_degraded_args(p):
    p.add_argument("motion", help="motion file (HDF5) from `voxpose motion`")
    p.add_argument("--rig", required=True, help="rig calibration file (JSON) the silhouettes are rendered with")
    p.add_argument("--params", default="{}", help="JSON: the config's `voxels` section")
    p.add_argument("--degradation", required=True, help='JSON: {"kind", "level", "band_px", "min_views"}')
    p.add_argument("--seed", type=int, default=0)
    _out(p)


def _voxelize_degraded(args):
    from voxpose.cli.pipeline import _log_counts, _voxel_meta
    from voxpose.motion.data import read_motion
    from voxpose.voxels.cameras import load_rig
    from voxpose.voxels.degrade import Degradation, voxelize_degraded
    from voxpose.voxels.sequence import write_voxels

    cfg, spec = _params(args.params), _params(args.degradation, "--degradation")
    motion, rig = read_motion(args.motion), load_rig(args.rig)
    degradation = Degradation(spec["kind"], spec["level"], args.seed, spec.get("band_px", 2))
    min_views = spec.get("min_views", cfg.get("min_views"))
    seq = voxelize_degraded(
        motion, rig, degradation, proportions=cfg.get("proportions") or None,
        follow_subject=cfg.get("follow_subject", True), l_res_fraction=cfg.get("l_res_fraction", 1 / 60),
        min_views=min_views, n_basis=cfg.get("n_basis", 200), seed=args.seed,
    )  # fmt: skip
    meta = _voxel_meta(rig, args.rig, cfg, motion.name) | {"degradation": spec, "min_views": min_views}
    meta |= {"motion": motion.name, "kind": motion.kind, "fps": motion.fps}
    write_voxels(args.output, seq, meta, angles=motion.angles)
    _log_counts(motion.name, seq)


def _predict_args(p):
    p.add_argument("features", help="per-frame features (HDF5) of the test motions")
    p.add_argument("motions", nargs="+", help="motion files (HDF5) of the test motions")
    p.add_argument("--regressor", required=True, help="regressor (HDF5) from `voxpose regress`")
    p.add_argument("--test", required=True, help="comma-separated test motion names")
    p.add_argument("--params", required=True, help="JSON: the config's `regression` section")
    _out(p)


def _predict(args):
    from voxpose.evaluation.run import evaluate, stored_predictors
    from voxpose.io.atomic import atomic_path
    from voxpose.io.hdf5 import read_arrays, read_per_motion
    from voxpose.motion.data import read_motion

    features, meta = read_per_motion(args.features, "features")
    motions = {m.name: m for m in map(read_motion, args.motions)}
    arrays, reg_meta = read_arrays(args.regressor, "regressor")
    predict = stored_predictors(arrays, reg_meta, _params(args.params).get("heading", "vector"))
    _, summary = evaluate(predict, features, motions, args.test.split(","))
    summary |= {"test": args.test.split(","), "regressor": args.regressor, "features": meta}
    m = summary["methods"]["mvrvm"]
    log.info("predict: %d test frames (%d gaps): full body %.2f deg, heading %.2f", summary["test_frames"],
             summary["test_gaps"], m["full_body"], m["heading"])  # fmt: skip
    with atomic_path(args.output) as tmp:
        tmp.write_text(json.dumps(summary, indent=1))


def _contexts_args(p):
    p.add_argument("motion", help="motion file (HDF5) from `voxpose motion`")
    p.add_argument("--rig", required=True, help="rig calibration file (JSON)")
    p.add_argument("--params", required=True, help="JSON: the config's `claims.contour` section")
    p.add_argument("--voxel-params", default="{}", help="JSON: the config's `voxels` section (body, placement)")
    _out(p)


def _contexts(args):
    from voxpose.features.silhouette import render_contexts
    from voxpose.io.hdf5 import write_arrays
    from voxpose.motion.data import read_motion
    from voxpose.voxels.cameras import load_rig

    cfg, vcfg = _params(args.params), _params(args.voxel_params, "--voxel-params")
    motion, rig = read_motion(args.motion), load_rig(args.rig)
    contexts, offsets = render_contexts(
        motion, rig, cfg, proportions=vcfg.get("proportions") or None, follow_subject=vcfg.get("follow_subject", True)
    )
    meta = {"motion": motion.name, "kind": motion.kind, "n_frames": motion.n_frames, "n_cameras": len(rig),
            "rig": rig.name, "params": cfg}  # fmt: skip
    write_arrays(args.output, "silhouette-contexts", {"contexts": contexts, "offsets": offsets}, meta)
    log.info("%s: %d shape contexts in %d images -> %s", motion.name, len(contexts), len(offsets) - 1, args.output)


def _read_contexts(path):
    from voxpose.io.hdf5 import read_arrays

    arrays, meta = read_arrays(path, "silhouette-contexts")
    return arrays["contexts"], arrays["offsets"], meta


def _fit_at_args(p):
    p.add_argument("contexts", nargs="+", help="shape-context files (HDF5) of the training motions")
    p.add_argument("--params", required=True, help="JSON: the config's `claims.at` section")
    p.add_argument("--cameras", required=True, help='JSON: "all" or a list of camera indices')
    p.add_argument("--seed", type=int, default=0)
    _out(p)


def _fit_at(args):
    from voxpose.features.silhouette import fit_codebook

    training = [(c, o, meta["n_cameras"]) for c, o, meta in map(_read_contexts, args.contexts)]
    model = fit_codebook(training, json.loads(args.cameras), _params(args.params), args.seed)
    model.save(args.output)


def _at_features_args(p):
    p.add_argument("model", help="codebook (HDF5) from `voxpose fit-silhouette-features`")
    p.add_argument("contexts", nargs="+", help="shape-context files (HDF5), one per motion")
    _out(p)


def _at_features(args):
    from voxpose.features.model import FeatureModel
    from voxpose.features.silhouette import silhouette_features
    from voxpose.io.hdf5 import write_per_motion

    model = FeatureModel.load(args.model)
    motions = {}
    for path in args.contexts:
        contexts, offsets, meta = _read_contexts(path)
        features, counts = silhouette_features(model, contexts, offsets, meta["n_cameras"])
        motions[meta["motion"]] = {"features": features, "counts": counts}
    write_per_motion(args.output, "features", motions, {"method": "agarwal-triggs", "model": model.meta})


def _figure_args(p):
    p.add_argument("--runs", required=True, help="JSON list of runs (see voxpose/evaluation/claims_figures.py)")
    p.add_argument("--png", required=True)
    p.add_argument("--csv", required=True)


def _figure(which):
    def run(args):
        from voxpose.evaluation import claims_figures, figures
        from voxpose.io.atomic import atomic_path

        table_of, draw = {
            "cameras": (claims_figures.camera_table, claims_figures.camera_figure),
            "robustness": (claims_figures.robustness_table, claims_figures.robustness_figure),
        }[which]
        table = table_of(json.loads(args.runs))
        with atomic_path(args.csv) as tmp:
            table.to_csv(tmp, index=False)
        figures.save(draw(table), args.png, "png")

    return run


COMMANDS = {
    "voxelize-degraded": ("motion -> degraded silhouettes -> carved voxels (HDF5)", _voxelize_degraded_args,
                          _voxelize_degraded),
    "transfer-predict": ("apply a trained regressor to other features: errors without retraining", _predict_args,
                         _predict),
    "silhouette-contexts": ("motion -> silhouettes -> 2D shape contexts per view (HDF5)", _contexts_args, _contexts),
    "fit-silhouette-features": ("fit the A&T K-means codebook on training shape contexts", _fit_at_args, _fit_at),
    "silhouette-features": ("shape contexts -> A&T soft histograms per frame", _at_features_args, _at_features),
    "camera-figure": ("error against camera rig: transferred, retrained, A&T", _figure_args, _figure("cameras")),
    "robustness-figure": ("error against silhouette degradation", _figure_args, _figure("robustness")),
}  # fmt: skip
