"""``voxpose predict``: a model applied to calibrated silhouettes or voxels -> BVH, CSV and a record."""

import logging

from voxpose.cli.common import check_suffix, non_negative_number, positive_number
from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

NAME = "predict"
HELP = "apply a model to calibrated silhouettes or voxels: BVH + CSV of angles"


def add_arguments(p):
    p.add_argument("model", help="model file (HDF5) from `voxpose export-model`")
    source = p.add_mutually_exclusive_group(required=True)
    source.add_argument("--silhouettes", help="folder with one PNG folder per camera (voxpose.voxels.silhouettes)")
    source.add_argument("--voxels", help="voxel file (HDF5) from `voxpose carve` or `voxpose voxelize`")
    p.add_argument("--rig", help="rig calibration file (JSON or YAML); needed with --silhouettes")
    p.add_argument("--pattern", help="silhouette file layout, e.g. '{camera}/img_{frame}.png' "
                   "(default '{camera}/{frame}.png'; voxpose/voxels/silhouettes.py)")  # fmt: skip
    p.add_argument(
        "--smooth",
        type=non_negative_number,
        default=0.0,
        help="Gaussian smoothing over time, sigma in frames (default 0: none, as in the paper)",
    )
    p.add_argument(
        "--fps", type=positive_number, help="frame rate of the BVH (default: the voxel file's, else the model's)"
    )
    p.add_argument("--csv", help="angles per frame (default: the output's name with .csv)")
    p.add_argument("--record", help="prediction record for `voxpose render` (default: the output's name with .h5)")
    p.add_argument(
        "-o",
        "--output",
        required=True,
        help="BVH file; frames with an empty hull are gaps: NaN rows in the CSV, rest pose in the BVH",
    )


def run(args):
    from voxpose.apply.model_file import load_model
    from voxpose.apply.outputs import write_outputs
    from voxpose.apply.predict import carve, check_voxels, predict_voxels

    out = check_suffix(args.output, "-o", ".bvh")
    csv_path = check_suffix(args.csv, "--csv", ".csv") if args.csv else out.with_suffix(".csv")
    record_path = check_suffix(args.record, "--record", ".h5") if args.record else out.with_suffix(".h5")
    if len({out.resolve(), csv_path.resolve(), record_path.resolve()}) < 3:
        raise VoxposeError(f"-o {out}: the BVH, CSV and record paths must differ")
    model = load_model(args.model)
    true_angles, fps = None, args.fps
    if args.silhouettes:
        from voxpose.voxels.cameras import load_rig
        from voxpose.voxels.plausibility import check_height, check_rig
        from voxpose.voxels.silhouettes import iter_silhouette_folder, silhouette_frame_numbers

        if not args.rig:
            raise VoxposeError("--silhouettes needs --rig (the cameras' calibration file)")
        rig = load_rig(args.rig)
        check_rig(rig, args.rig)
        frames = silhouette_frame_numbers(args.silhouettes, rig, args.pattern)
        seq = carve(model, iter_silhouette_folder(args.silhouettes, rig, args.pattern), rig, n_frames=len(frames),
                    name=str(args.silhouettes))  # fmt: skip
        check_height(seq.h_sub, args.rig)
        source = {"silhouettes": str(args.silhouettes), "rig": rig.name}
    else:
        from voxpose.voxels.sequence import read_voxels

        seq, meta, true_angles = read_voxels(args.voxels)
        check_voxels(model, seq, meta, args.voxels)
        # carve's frame numbers, else 0, 1, ...
        frames, fps = meta.get("frames"), fps if fps is not None else meta.get("fps")
        source = {"voxels": str(args.voxels)}
    prediction = predict_voxels(model, seq, frames=frames, fps=fps, true_angles=true_angles, smooth=args.smooth,
                                name=str(args.silhouettes or args.voxels))  # fmt: skip
    meta = {"model": str(args.model), "source": source, "novelty": prediction.novelty}
    write_outputs(prediction, prediction.skeleton, out, csv_path, record_path, meta)
    n_gaps = int((~prediction.valid).sum())
    log.info("predict: %d frames (%d gaps) -> %s, %s, %s", len(prediction.valid), n_gaps, out, csv_path,
             record_path)  # fmt: skip
    error = prediction.error()
    if error is not None:
        log.info("predict: full-body error against the voxel file's true poses: %.3f deg", error)
