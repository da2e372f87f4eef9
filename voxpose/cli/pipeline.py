"""The subcommands of ``voxpose``: each reads its inputs, calls the library and writes its outputs atomically.

``COMMANDS`` maps a name to ``(help, add_arguments(parser), run(args))``; ``voxpose.cli.main`` builds the parser
from it. Library modules are imported inside each ``run`` so that ``voxpose --help`` stays fast.
"""

import json
import logging
from pathlib import Path

from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")


def _params(text: str, what: str = "--params") -> dict:
    try:
        value = json.loads(text)
    except json.JSONDecodeError as err:
        raise VoxposeError(f"{what}: not valid JSON ({err})") from None
    if not isinstance(value, dict):
        raise VoxposeError(f"{what}: expected a JSON object")
    return value


def _out(p):
    p.add_argument("-o", "--output", required=True, help="output file")


# --- motions ---


def _generate_args(p):
    p.add_argument("--kind", required=True, choices=["walk", "drunk", "spiral", "jog", "jump"])
    p.add_argument("--index", type=int, required=True, help="sequence number within its kind")
    p.add_argument("--frames", type=int, required=True)
    p.add_argument("--seed", type=int, required=True, help="master seed of the generated set")
    _out(p)


def _generate(args):
    from voxpose.io.bvh import write_bvh
    from voxpose.motion.generate import default_motion

    write_bvh(default_motion(args.kind, args.index, n_frames=args.frames, seed=args.seed), args.output)
    log.info("generated %s %d (%d frames, seed %d) -> %s", args.kind, args.index, args.frames, args.seed, args.output)


def _derive_args(p):
    p.add_argument("source", help="a real motion (BVH): a straight walk for spiral and drunk")
    p.add_argument("--kind", required=True, choices=["spiral", "drunk", "turn"])
    p.add_argument("--seed", type=int, required=True)
    p.add_argument("--params", default="{}", help='JSON: transform parameters, e.g. {"degrees": 180} for turn')
    _out(p)


def _derive(args):
    from voxpose.motion.derive import derive_file, derived_name

    out = Path(args.output)
    params = _params(args.params)
    expected = f"{derived_name(args.kind, Path(args.source).stem, params)}.bvh"
    if out.name != expected:
        raise VoxposeError(f"-o {out}: a derived {args.kind} motion of {args.source} must be named {expected}")
    _, provenance = derive_file(args.source, args.kind, out.parent, args.seed, params)
    log.info("derived %s: %s", out, json.dumps(provenance))


def _motion_args(p):
    p.add_argument("bvh", help="BVH file")
    p.add_argument("--params", default="{}", help="JSON: the config's `motions` section")
    _out(p)


def _motion(args):
    from voxpose.motion.data import write_motion
    from voxpose.motion.load import load_motion

    cfg = _params(args.params)
    motion = load_motion(
        args.bvh,
        fps=cfg.get("fps", 30.0),
        unit_scale=cfg.get("unit_scale"),
        joint_map=cfg.get("joint_map"),
        drop_reference_frame=cfg.get("drop_reference_frame", "auto"),
    )
    write_motion(args.output, motion)
    log.info("%s: %d frames at %g fps, height %.2f m", motion.name, motion.n_frames, motion.fps, motion.height)


# --- voxels ---


def _rig_args(p):
    p.add_argument("--params", required=True, help="JSON: the config's `rig` section")
    _out(p)


def _rig(args):
    from voxpose.voxels.cameras import circular_rig, load_rig, save_rig

    cfg = _params(args.params)
    if cfg.get("file"):
        rig = load_rig(cfg["file"])
    else:
        rig = circular_rig(
            n=cfg["n_cameras"],
            radius=cfg["radius"],
            height=cfg["height"],
            focal_px=cfg["focal_px"],
            width=cfg["width"],
            image_height=cfg["image_height"],
            target=(0.0, cfg["target_height"], 0.0),
            name=cfg["name"],
        )
    save_rig(rig, args.output)
    log.info("rig %s: %d cameras -> %s", rig.name, len(rig), args.output)


def _voxel_meta(rig, rig_path, cfg, source: str) -> dict:
    """Provenance of a voxel file: the rig's calibration as given, the parameters, the source."""
    return {"source": source, "rig": rig.name, "rig_calibration": Path(rig_path).read_text(), "params": cfg}


def _voxelize_args(p):
    p.add_argument("motion", help="motion file (HDF5) from `voxpose motion`")
    p.add_argument("--rig", required=True, help="rig calibration file (JSON)")
    p.add_argument("--params", default="{}", help="JSON: the config's `voxels` section")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--export-silhouettes", metavar="DIR", help="also write the rendered silhouettes as PNG folders")
    _out(p)


def _voxelize(args):
    from voxpose.motion.data import read_motion
    from voxpose.voxels.cameras import load_rig
    from voxpose.voxels.sequence import write_voxels
    from voxpose.voxels.voxelize import voxelize_motion

    cfg = _params(args.params)
    motion, rig = read_motion(args.motion), load_rig(args.rig)
    seq = voxelize_motion(
        motion,
        rig,
        proportions=cfg.get("proportions") or None,
        l_res_fraction=cfg.get("l_res_fraction", 1 / 60),
        min_views=cfg.get("min_views"),
        n_basis=cfg.get("n_basis", 200),
        seed=args.seed,
        follow_subject=cfg.get("follow_subject", True),
        keep_silhouettes=bool(args.export_silhouettes),
    )
    if args.export_silhouettes:
        from voxpose.voxels.silhouettes import write_silhouette_folder

        write_silhouette_folder(seq.silhouettes, rig, args.export_silhouettes)
    meta = _voxel_meta(rig, args.rig, cfg, motion.name)
    meta |= {"motion": motion.name, "kind": motion.kind, "fps": motion.fps}
    write_voxels(args.output, seq, meta, angles=motion.angles)
    _log_counts(motion.name, seq)


def _log_counts(name, seq):
    counts = seq.counts()
    log.info(
        "%s: %d frames, l_res %.4f m, h_sub %.3f m; mean voxels %.0f, surface %.0f, basis %.0f; %d empty",
        name, seq.n_frames, seq.l_res, seq.h_sub, counts["occupied"].mean(), counts["surface"].mean(),
        counts["basis"].mean(), int(seq.empty.sum()),
    )  # fmt: skip


def _carve_args(p):
    p.add_argument("--rig", required=True, help="rig calibration file (JSON or YAML, see voxpose/voxels/cameras.py)")
    p.add_argument("--silhouettes", required=True, help="folder with one PNG folder per camera")
    p.add_argument("--l-res-fraction", type=float, default=1 / 60, help="voxel size / subject height")
    p.add_argument("--min-views", type=int, default=None, help="occupied if inside at least this many views")
    p.add_argument("--n-basis", type=int, default=200)
    p.add_argument("--seed", type=int, default=0)
    _out(p)


def _carve(args):
    from voxpose.voxels.cameras import load_rig
    from voxpose.voxels.sequence import write_voxels
    from voxpose.voxels.silhouettes import iter_silhouette_folder
    from voxpose.voxels.voxelize import voxelize_silhouettes

    rig = load_rig(args.rig)
    seq = voxelize_silhouettes(
        iter_silhouette_folder(args.silhouettes, rig),
        rig,
        l_res_fraction=args.l_res_fraction,
        min_views=args.min_views,
        n_basis=args.n_basis,
        seed=args.seed,
        name=str(args.silhouettes),
    )
    cfg = {"l_res_fraction": args.l_res_fraction, "min_views": args.min_views, "n_basis": args.n_basis}
    write_voxels(args.output, seq, _voxel_meta(rig, args.rig, cfg, str(args.silhouettes)))
    _log_counts(str(args.silhouettes), seq)


# --- descriptors ---


def _describe_args(p):
    p.add_argument("voxels", help="voxel file (HDF5) from `voxpose voxelize` or `voxpose carve`")
    p.add_argument("--params", default="{}", help="JSON: the config's `descriptor` section")
    _out(p)


def _describe(args):
    import numpy as np

    from voxpose.descriptors.file import write_descriptors
    from voxpose.descriptors.lut import ShapeContextTable
    from voxpose.voxels.sequence import read_voxels

    cfg = _params(args.params)
    seq, meta, _ = read_voxels(args.voxels)
    table = ShapeContextTable(seq.h_sub / seq.l_res, **cfg)
    surface_basis = [(ijk[surface], ijk[basis]) for ijk, surface, basis in map(seq.frame, range(seq.n_frames))]
    carved = np.flatnonzero(~seq.empty)  # frames with an empty hull stay gaps: no descriptors
    descriptors = [np.zeros((0, table.n_bins)) for _ in surface_basis]
    described = table.describe_frames((surface_basis[f] for f in carved), threads=args.threads)
    for f, desc in zip(carved, described, strict=True):
        descriptors[f] = desc
    basis_ijk = [basis for _, basis in surface_basis]
    out_meta = {
        "params": cfg,
        "motion": meta.get("motion"),
        "kind": meta.get("kind"),
        "l_res": seq.l_res,
        "h_sub": seq.h_sub,
        "empty": seq.empty.tolist(),
    }
    write_descriptors(args.output, descriptors, basis_ijk, out_meta)
    n_desc = sum(map(len, descriptors))
    log.info("describe: %d frames, %d descriptors -> %s", seq.n_frames, n_desc, args.output)


# --- features ---


def _fit_features_args(p):
    p.add_argument("descriptors", nargs="+", help="descriptor files (HDF5) of the training motions")
    p.add_argument("--method", required=True, choices=["mppca", "kmeans"])
    p.add_argument("--params", required=True, help="JSON: the config's `features` section")
    p.add_argument("--seed", type=int, default=0)
    _out(p)


def _fit_features(args):
    import numpy as np

    from voxpose.descriptors.file import read_descriptors
    from voxpose.features.model import FeatureModel

    rows = [d for path in args.descriptors for d in read_descriptors(path)[0] if len(d)]
    model = FeatureModel.fit(args.method, np.concatenate(rows), _params(args.params), args.seed)
    model.save(args.output)


def _features_args(p):
    p.add_argument("model", help="feature model (HDF5) from `voxpose fit-features`")
    p.add_argument("descriptors", nargs="+", help="descriptor files (HDF5), one per motion")
    _out(p)


def _features(args):
    import numpy as np

    from voxpose.descriptors.file import read_descriptors
    from voxpose.features.model import FeatureModel
    from voxpose.io.hdf5 import write_per_motion

    model = FeatureModel.load(args.model)
    motions = {}
    for path in args.descriptors:
        frames, _, meta = read_descriptors(path)
        frame_index = np.repeat(np.arange(len(frames)), [len(d) for d in frames])
        features, counts = model.transform(np.concatenate(frames), frame_index, len(frames))
        motions[meta["motion"]] = {"features": features, "counts": counts}
        log.info("features %s: %d frames, %d gaps", meta["motion"], len(frames), int((counts == 0).sum()))
    write_per_motion(args.output, "features", motions, {"method": model.method, "model": model.meta})


# --- regression and evaluation ---


def _regress_args(p):
    p.add_argument("features", help="per-frame features (HDF5) from `voxpose features`")
    p.add_argument("motions", nargs="+", help="motion files (HDF5) of the experiment's motions")
    p.add_argument("--train", required=True, help="comma-separated training motion names")
    p.add_argument("--test", required=True, help="comma-separated test motion names")
    p.add_argument("--params", required=True, help="JSON: the config's `regression` section")
    p.add_argument("--seed", type=int, default=0)
    for name in ("model", "predictions", "angles", "summary"):
        p.add_argument(f"--{name}", required=True, help=f"output: {name}")


def _regress(args):
    import pandas as pd

    from voxpose.evaluation.run import run
    from voxpose.io.atomic import atomic_path
    from voxpose.io.hdf5 import read_per_motion, write_arrays, write_per_motion
    from voxpose.motion import canon
    from voxpose.motion.data import read_motion
    from voxpose.regression.stored import regressor_arrays

    features, _ = read_per_motion(args.features, "features")
    motions = {m.name: m for m in map(read_motion, args.motions)}
    result = run(features, motions, args.train.split(","), args.test.split(","), _params(args.params), args.seed)
    write_arrays(args.model, "regressor", *regressor_arrays(result.pca, result.mvrvm))
    write_per_motion(args.predictions, "predictions", result.predictions, {"summary": result.summary})
    frames = []
    for name, p in result.predictions.items():
        df = pd.DataFrame(p["pred_mvrvm"], columns=canon.ANGLE_NAMES)
        df.insert(0, "frame", range(len(df)))
        df.insert(0, "motion", name)
        frames.append(df)
    with atomic_path(args.angles) as tmp:
        pd.concat(frames).to_csv(tmp, index=False, float_format="%.4f")
    with atomic_path(args.summary) as tmp:
        tmp.write_text(json.dumps(result.summary, indent=1))


def _table_args(which):
    def add(p):
        if which == 1:
            p.add_argument("--ours", required=True, help="summary.json of MPPCA + MVRVM")
            p.add_argument("--kmeans", required=True, help="summary.json of K-means + MVRVM")
            p.add_argument("--at-one", help="summary.json of the Agarwal & Triggs-style run on one camera")
            p.add_argument("--at-all", help="summary.json of the Agarwal & Triggs-style run on all cameras")
        else:
            p.add_argument("--summary", required=True, help="summary.json of the five-type regressor")
        p.add_argument("--csv", required=True)
        p.add_argument("--md", required=True)

    return add


def _table1(args):
    from voxpose.evaluation.tables import AT_ALL_LABEL, AT_ONE_LABEL, read_summary, table1, write_table

    at = {label: read_summary(path) for label, path in ((AT_ONE_LABEL, args.at_one), (AT_ALL_LABEL, args.at_all))
          if path}  # fmt: skip
    df = table1(read_summary(args.ours), read_summary(args.kmeans), at)
    write_table(df, args.csv, args.md, "Table 1: RMS error (degrees) on the held-out spiral walk")


def _table2(args):
    from voxpose.evaluation.tables import read_summary, table2, write_table

    df = table2(read_summary(args.summary))
    write_table(df, args.csv, args.md, "Table 2: one regressor for five motion types, RMS error (degrees)")


def _figure4_args(p):
    p.add_argument("--runs", required=True, help="JSON list of [sweep, value, summary.json]")
    p.add_argument("--png", required=True)
    p.add_argument("--pdf", required=True)
    p.add_argument("--csv", required=True)


def _figure4(args):
    from voxpose.evaluation import figures
    from voxpose.io.atomic import atomic_path

    runs = json.loads(args.runs)
    table = figures.figure4_table(runs)
    with atomic_path(args.csv) as tmp:
        table.to_csv(tmp, index=False)
    fig = figures.figure4(table)
    figures.save(fig, args.png, "png")
    figures.save(fig, args.pdf, "pdf")


def _joint_errors_args(p):
    p.add_argument("--summary", action="append", required=True, help="NAME=summary.json (repeatable)")
    _out(p)


def _joint_errors(args):
    from voxpose.evaluation import figures

    figures.save(figures.joint_errors(figures.summaries_from(args.summary)), args.output, "png")


def _error_over_time_args(p):
    p.add_argument("--predictions", action="append", required=True, help="NAME=predictions.h5 (repeatable)")
    _out(p)


def _error_over_time(args):
    from voxpose.evaluation import figures
    from voxpose.io.hdf5 import read_per_motion

    series = {}
    for pair in args.predictions:
        title, path = pair.split("=", 1)
        motions, _ = read_per_motion(path, "predictions")
        series[title] = {name: p["frame_error_mvrvm"] for name, p in motions.items()}
    figures.save(figures.error_over_time(series), args.output, "png")


def _gallery_args(p):
    p.add_argument("predictions", help="predictions (HDF5) from `voxpose regress`")
    p.add_argument("voxels", nargs="+", help="voxel files (HDF5) of the test motions")
    p.add_argument("--per-kind", type=int, default=3, help="frames shown per motion type")
    _out(p)


def _gallery(args):
    from voxpose.evaluation import figures
    from voxpose.evaluation.gallery import gallery
    from voxpose.io.hdf5 import read_per_motion
    from voxpose.voxels.sequence import read_voxels

    predictions, _ = read_per_motion(args.predictions, "predictions")
    voxels = {}
    for path in args.voxels:
        seq, meta, _ = read_voxels(path)
        voxels[meta["motion"]] = (seq, meta)
    figures.save(gallery(predictions, voxels, per_kind=args.per_kind), args.output, "png")


COMMANDS = {
    "generate": ("write one motion of the embedded default set as BVH", _generate_args, _generate),
    "derive": ("derive a spiral or drunken walk, or a turned copy, from a real motion (BVH)", _derive_args, _derive),
    "motion": ("BVH -> canonical 42-angle poses (HDF5)", _motion_args, _motion),
    "rig": ("write the calibration file of the configured camera rig", _rig_args, _rig),
    "voxelize": ("motion -> body model -> silhouettes -> carved voxels (HDF5)", _voxelize_args, _voxelize),
    "carve": ("calibrated multi-view PNG silhouettes -> carved voxels (HDF5)", _carve_args, _carve),
    "describe": ("voxels -> 3D shape contexts at the basis voxels (HDF5)", _describe_args, _describe),
    "fit-features": ("fit MPPCA or K-means on training descriptors", _fit_features_args, _fit_features),
    "features": ("descriptors -> one feature vector per frame (Eq. 5 or K-means)", _features_args, _features),
    "regress": ("pose PCA + MVRVM on an experiment: predictions and errors", _regress_args, _regress),
    "table1": ("Table 1 from run summaries (CSV + Markdown)", _table_args(1), _table1),
    "table2": ("Table 2 from a run summary (CSV + Markdown)", _table_args(2), _table2),
    "figure4": ("Figure 4 from the cross-validation sweep summaries", _figure4_args, _figure4),
    "joint-errors": ("bar chart of the error per joint", _joint_errors_args, _joint_errors),
    "error-over-time": ("per-frame error along the test motions", _error_over_time_args, _error_over_time),
    "gallery": ("Figure 5-style gallery: voxels with estimated and true skeletons", _gallery_args, _gallery),
}
