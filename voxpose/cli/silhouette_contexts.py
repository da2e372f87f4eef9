"""``voxpose silhouette-contexts``: a motion -> silhouettes -> 2D shape contexts per view (Agarwal & Triggs)."""

import logging

from voxpose.cli.common import add_output, parse_params, seed
from voxpose.config_schema import section

log = logging.getLogger("voxpose")

NAME = "silhouette-contexts"
HELP = "motion -> silhouettes -> 2D shape contexts per view (HDF5)"


def add_arguments(p):
    p.add_argument("motion", help="motion file (HDF5) from `voxpose motion`")
    p.add_argument("--rig", required=True, help="rig calibration file (JSON)")
    p.add_argument("--params", required=True, help="JSON: the config's `claims.contour` section")
    p.add_argument("--voxel-params", default="{}", help="JSON: the config's `voxels` section (body, placement)")
    p.add_argument("--seed", type=seed, default=0, help="the config's seed (draws the body variation)")
    add_output(p)


def run(args):
    from voxpose.descriptors.file import write_contours
    from voxpose.features.silhouette import render_contexts
    from voxpose.motion.data import read_motion
    from voxpose.voxels.cameras import load_rig
    from voxpose.voxels.settings import VoxelSettings

    cfg = parse_params(args.params, schema=section("claims", "contour"))
    vcfg = parse_params(args.voxel_params, "--voxel-params", section("voxels", required=False))
    settings = VoxelSettings.from_config(vcfg, "--voxel-params")
    motion, rig = read_motion(args.motion), load_rig(args.rig)
    contexts, offsets = render_contexts(
        motion, rig, cfg, proportions=settings.proportions or None,
        variation=settings.body_variation(motion.name, args.seed), follow_subject=settings.follow_subject,
    )  # fmt: skip
    meta = {"motion": motion.name, "kind": motion.kind, "n_frames": motion.n_frames, "n_cameras": len(rig),
            "rig": rig.name, "params": cfg}  # fmt: skip
    write_contours(args.output, contexts, offsets, meta)
    log.info("%s: %d shape contexts in %d images -> %s", motion.name, len(contexts), len(offsets) - 1, args.output)
