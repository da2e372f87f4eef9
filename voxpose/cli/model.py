"""Subcommands that use a trained model on new data: ``export-model``, ``predict`` and ``render``.

``COMMANDS`` has the shape of ``voxpose.cli.pipeline.COMMANDS``.
"""

import logging
from pathlib import Path

from voxpose.cli.pipeline import _params
from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")


def _export_args(p):
    p.add_argument("--feature-model", required=True, help="feature model (HDF5) from `voxpose fit-features`")
    p.add_argument("--regressor", required=True, help="regressor (HDF5) from `voxpose regress`")
    p.add_argument("--summary", required=True, help="summary.json of the same run (kept as provenance)")
    p.add_argument("--motions", nargs="+", required=True, help="motion files (HDF5) of the training motions")
    p.add_argument("--voxels", required=True, help="JSON: the config's `voxels` section")
    p.add_argument("--descriptor", required=True, help="JSON: the config's `descriptor` section")
    p.add_argument("--regression", required=True, help="JSON: the config's `regression` section")
    p.add_argument("--seed", type=int, required=True, help="master seed (the basis voxels' seed)")
    p.add_argument("--name", default="", help="label kept in the model's provenance (experiment/rig/...)")
    p.add_argument("-o", "--output", required=True, help="model file (HDF5)")


def _export(args):
    from voxpose import __version__
    from voxpose.apply.model_file import PoseModel, save_model, voxel_settings
    from voxpose.evaluation.tables import read_summary
    from voxpose.features.model import FeatureModel
    from voxpose.io.hdf5 import read_arrays
    from voxpose.motion.data import read_motion
    from voxpose.motion.output_skeleton import OutputSkeleton
    from voxpose.regression.stored import regressor_from_arrays

    motions = [read_motion(p) for p in args.motions]
    pca, mvrvm = regressor_from_arrays(*read_arrays(args.regressor, "regressor"))
    summary = read_summary(args.summary)
    train = sorted(m.name for m in motions)
    if sorted(summary["train"]) != train:
        raise VoxposeError(f"--motions: {', '.join(train)} are not the training motions of {args.summary}")
    fps = {m.fps for m in motions}
    if len(fps) != 1:
        raise VoxposeError(f"--motions: the training motions have different frame rates {sorted(fps)}")
    model = PoseModel(
        voxels=voxel_settings(_params(args.voxels, "--voxels"), args.seed),
        descriptor=_params(args.descriptor, "--descriptor"),
        features=FeatureModel.load(args.feature_model),
        pca=pca,
        mvrvm=mvrvm,
        heading=_params(args.regression, "--regression").get("heading", "vector"),
        skeleton=OutputSkeleton.from_motions(motions),
        fps=fps.pop(),
        provenance={"name": args.name, "train": train, "test": summary["test"], "voxpose": __version__,
                    "test_errors": {m: {k: v for k, v in e.items() if not isinstance(v, dict)}
                                    for m, e in summary["methods"].items()}},
    )  # fmt: skip
    save_model(args.output, model)
    log.info("model %s: %s features, M = %d, %d relevance vectors -> %s", args.name, model.features.method,
             pca.n_components_, len(mvrvm.relevance_), args.output)  # fmt: skip


def _predict_args(p):
    p.add_argument("model", help="model file (HDF5) from `voxpose export-model`")
    source = p.add_mutually_exclusive_group(required=True)
    source.add_argument("--silhouettes", help="folder with one PNG folder per camera (voxpose.voxels.silhouettes)")
    source.add_argument("--voxels", help="voxel file (HDF5) from `voxpose carve` or `voxpose voxelize`")
    p.add_argument("--rig", help="rig calibration file (JSON or YAML); needed with --silhouettes")
    p.add_argument(
        "--smooth",
        type=float,
        default=0.0,
        help="Gaussian smoothing over time, sigma in frames (default 0: none, as in the paper)",
    )
    p.add_argument("--fps", type=float, help="frame rate of the BVH (default: the voxel file's, else the model's)")
    p.add_argument("--csv", help="angles per frame (default: the output's name with .csv)")
    p.add_argument("--record", help="prediction record for `voxpose render` (default: the output's name with .h5)")
    p.add_argument(
        "-o",
        "--output",
        required=True,
        help="BVH file; frames with an empty hull are gaps: NaN rows in the CSV, rest pose in the BVH",
    )


def _predict(args):
    from voxpose.apply.model_file import load_model
    from voxpose.apply.outputs import write_outputs
    from voxpose.apply.predict import carve, check_voxels, predict_voxels

    out = Path(args.output)
    csv_path = Path(args.csv) if args.csv else out.with_suffix(".csv")
    record_path = Path(args.record) if args.record else out.with_suffix(".h5")
    if len({out.resolve(), csv_path.resolve(), record_path.resolve()}) < 3:
        raise VoxposeError(f"-o {out}: the BVH, CSV and record paths must differ")
    model = load_model(args.model)
    true_angles, fps = None, args.fps
    if args.silhouettes:
        from voxpose.voxels.cameras import load_rig
        from voxpose.voxels.silhouettes import iter_silhouette_folder, silhouette_frame_numbers

        if not args.rig:
            raise VoxposeError("--silhouettes needs --rig (the cameras' calibration file)")
        rig = load_rig(args.rig)
        frames = silhouette_frame_numbers(args.silhouettes, rig)
        seq = carve(model, iter_silhouette_folder(args.silhouettes, rig), rig, n_frames=len(frames),
                    name=str(args.silhouettes))  # fmt: skip
        source = {"silhouettes": str(args.silhouettes), "rig": rig.name}
    else:
        from voxpose.voxels.sequence import read_voxels

        seq, meta, true_angles = read_voxels(args.voxels)
        check_voxels(model, seq, meta, args.voxels)
        frames, fps = None, fps or meta.get("fps")
        source = {"voxels": str(args.voxels)}
    prediction = predict_voxels(model, seq, frames=frames, fps=fps, true_angles=true_angles, smooth=args.smooth)
    meta = {"model": str(args.model), "source": source}
    write_outputs(prediction, model.skeleton, out, csv_path, record_path, meta)
    n_gaps = int((~prediction.valid).sum())
    log.info("predict: %d frames (%d gaps) -> %s, %s, %s", len(prediction.valid), n_gaps, out, csv_path,
             record_path)  # fmt: skip
    error = prediction.error()
    if error is not None:
        log.info("predict: full-body error against the voxel file's true poses: %.3f deg", error)


def _render_args(p):
    p.add_argument("record", help="prediction record (HDF5) from `voxpose predict`")
    p.add_argument("--truth", help="true motion: a motion file (HDF5) from `voxpose motion`, or a BVH file")
    p.add_argument("--every", type=int, default=1, help="draw every n-th frame (default 1)")
    p.add_argument("--fps", type=float, help="playback rate (default: the prediction's frame rate)")
    p.add_argument("-o", "--output", required=True, help="animated GIF")


def _render(args):
    from voxpose.apply.animation import render_gif
    from voxpose.apply.outputs import read_record

    if Path(args.output).suffix.lower() != ".gif":
        raise VoxposeError(f"-o {args.output}: render writes animated GIF files (.gif)")
    prediction, skeleton, _ = read_record(args.record)
    if args.truth:
        prediction.true_angles = _truth_angles(args.truth, len(prediction.valid))
    n = render_gif(prediction, skeleton.offsets, args.output, every=args.every, fps=args.fps)
    log.info("render: %d frames -> %s", n, args.output)


def _truth_angles(path, n_frames):
    if Path(path).suffix.lower() == ".bvh":
        from voxpose.motion.load import load_motion

        angles = load_motion(path).angles
    else:
        from voxpose.motion.data import read_motion

        angles = read_motion(path).angles
    if len(angles) != n_frames:
        raise VoxposeError(f"--truth {path}: {len(angles)} frames, the prediction has {n_frames}")
    return angles


COMMANDS = {
    "export-model": ("bundle a trained pipeline into one model file (HDF5)", _export_args, _export),
    "predict": ("apply a model to calibrated silhouettes or voxels: BVH + CSV of angles", _predict_args, _predict),
    "render": ("animated GIF of a prediction: voxels with estimated (and true) skeleton", _render_args, _render),
}
