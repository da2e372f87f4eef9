"""``voxpose carve``: calibrated multi-view PNG silhouettes -> carved voxels (Section 4), as the workflow carves."""

from voxpose.cli.common import add_output, log_counts, positive_integer, positive_number, seed, voxel_meta
from voxpose.voxels.settings import DEFAULTS, VoxelSettings

NAME = "carve"
HELP = "calibrated multi-view PNG silhouettes -> carved voxels (HDF5)"


def add_arguments(p):
    p.add_argument("--rig", required=True, help="rig calibration file (JSON or YAML, see voxpose/voxels/cameras.py)")
    p.add_argument("--silhouettes", required=True, help="folder with one PNG folder per camera")
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
    from voxpose.voxels.sequence import write_voxels
    from voxpose.voxels.silhouettes import iter_silhouette_folder
    from voxpose.voxels.voxelize import voxelize_silhouettes

    settings = VoxelSettings(l_res_fraction=args.l_res_fraction, min_views=args.min_views, n_basis=args.n_basis)
    rig = load_rig(args.rig)
    seq = voxelize_silhouettes(
        iter_silhouette_folder(args.silhouettes, rig), rig, seed=args.seed, name=str(args.silhouettes),
        **settings.carving()
    )  # fmt: skip
    cfg = settings.carving()
    write_voxels(args.output, seq, voxel_meta(rig, args.rig, cfg, str(args.silhouettes)))
    log_counts(str(args.silhouettes), seq)
