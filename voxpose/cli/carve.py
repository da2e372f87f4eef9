"""``voxpose carve``: calibrated multi-view PNG silhouettes -> carved voxels (Section 4), as the workflow carves."""

from voxpose.cli.common import add_output, log_counts, positive_integer, positive_number, seed, voxel_meta
from voxpose.voxels.settings import DEFAULTS, VoxelSettings

NAME = "carve"
HELP = "calibrated multi-view PNG silhouettes -> carved voxels (HDF5)"


def add_arguments(p):
    p.add_argument("--rig", required=True, help="rig calibration file (JSON or YAML, see voxpose/voxels/cameras.py)")
    p.add_argument("--silhouettes", required=True, help="folder with one PNG folder per camera")
    p.add_argument("--pattern", help="silhouette file layout, e.g. '{camera}/img_{frame}.png' "
                   "(default '{camera}/{frame}.png'; voxpose/voxels/silhouettes.py)")  # fmt: skip
    p.add_argument(
        "--l-res-fraction", type=positive_number, default=DEFAULTS.l_res_fraction, help="voxel size / subject height"
    )
    p.add_argument(
        "--min-views", type=positive_integer, default=DEFAULTS.min_views, help="occupied if inside >= this many views"
    )
    p.add_argument("--n-basis", type=positive_integer, default=DEFAULTS.n_basis, help="basis voxels per frame")
    p.add_argument("--seed", type=seed, default=0)
    add_output(p)


def run(args):
    from voxpose.voxels.cameras import load_rig
    from voxpose.voxels.plausibility import check_height, check_rig
    from voxpose.voxels.sequence import write_voxels
    from voxpose.voxels.silhouettes import iter_silhouette_folder, silhouette_frame_numbers
    from voxpose.voxels.voxelize import voxelize_silhouettes

    settings = VoxelSettings(l_res_fraction=args.l_res_fraction, min_views=args.min_views, n_basis=args.n_basis)
    rig = load_rig(args.rig)
    check_rig(rig, args.rig)
    frames = silhouette_frame_numbers(args.silhouettes, rig, args.pattern)
    seq = voxelize_silhouettes(
        iter_silhouette_folder(args.silhouettes, rig, args.pattern), rig, seed=args.seed,
        name=str(args.silhouettes), n_frames=len(frames), **settings.carving()
    )  # fmt: skip
    check_height(seq.h_sub, args.rig)
    cfg = settings.carving()
    meta = voxel_meta(rig, args.rig, cfg, str(args.silhouettes)) | {"frames": [int(f) for f in frames]}
    write_voxels(args.output, seq, meta)
    log_counts(str(args.silhouettes), seq)
