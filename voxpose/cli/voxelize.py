"""``voxpose voxelize``: a motion -> body model -> silhouettes -> carved, surface and basis voxels (Sections 4, 6)."""

from voxpose.cli.common import add_output, log_counts, parse_params, seed, voxel_meta
from voxpose.config_schema import section

NAME = "voxelize"
HELP = "motion -> body model -> silhouettes -> carved voxels (HDF5)"


def add_arguments(p):
    p.add_argument("motion", help="motion file (HDF5) from `voxpose motion`")
    p.add_argument("--rig", required=True, help="rig calibration file (JSON)")
    p.add_argument("--params", default="{}", help="JSON: the config's `voxels` section")
    p.add_argument("--seed", type=seed, default=0)
    p.add_argument("--export-silhouettes", metavar="DIR", help="also write the rendered silhouettes as PNG folders")
    add_output(p)


def run(args):
    from voxpose.motion.data import read_motion
    from voxpose.voxels.cameras import load_rig
    from voxpose.voxels.sequence import write_voxels
    from voxpose.voxels.settings import VoxelSettings
    from voxpose.voxels.voxelize import voxelize_motion

    cfg = parse_params(args.params, schema=section("voxels", required=False))
    settings = VoxelSettings.from_config(cfg, "--params")
    motion, rig = read_motion(args.motion), load_rig(args.rig)
    seq = voxelize_motion(
        motion,
        rig,
        proportions=settings.proportions or None,
        variation=settings.body_variation(motion.name, args.seed),
        seed=args.seed,
        follow_subject=settings.follow_subject,
        keep_silhouettes=bool(args.export_silhouettes),
        **settings.carving(),
    )
    if args.export_silhouettes:
        from voxpose.voxels.silhouettes import write_silhouette_folder

        write_silhouette_folder(seq.silhouettes, rig, args.export_silhouettes)
    meta = voxel_meta(rig, args.rig, cfg, motion.name)
    meta |= {"motion": motion.name, "kind": motion.kind, "fps": motion.fps}
    write_voxels(args.output, seq, meta, angles=motion.angles)
    log_counts(motion.name, seq)
