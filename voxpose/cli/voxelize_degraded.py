"""``voxpose voxelize-degraded``: silhouettes degraded as real segmentation degrades them, then carved."""

from voxpose.cli.common import add_output, log_counts, parse_params, seed, voxel_meta
from voxpose.config_schema import section

# one degradation of the robustness study (voxpose.workflow_config.degraded_sets); the level's range per kind is
# checked by voxpose.voxels.degrade.Degradation
DEGRADATION = {
    "type": "object", "additionalProperties": False, "required": ["kind", "level"],
    "properties": {"kind": {"enum": ["none", "flip", "morph", "limb", "calibration"]}, "level": {"type": "number"},
                   "band_px": {"type": "integer", "minimum": 1},
                   "min_views": {"type": ["integer", "null"], "minimum": 1}},
}  # fmt: skip

NAME = "voxelize-degraded"
HELP = "motion -> degraded silhouettes -> carved voxels (HDF5)"


def add_arguments(p):
    p.add_argument("motion", help="motion file (HDF5) from `voxpose motion`")
    p.add_argument("--rig", required=True, help="rig calibration file (JSON) the silhouettes are rendered with")
    p.add_argument("--params", default="{}", help="JSON: the config's `voxels` section")
    p.add_argument("--degradation", required=True, help='JSON: {"kind", "level", "band_px", "min_views"}')
    p.add_argument("--seed", type=seed, default=0)
    add_output(p)


def run(args):
    from voxpose.motion.data import read_motion
    from voxpose.voxels.cameras import load_rig
    from voxpose.voxels.degrade import Degradation, voxelize_degraded
    from voxpose.voxels.sequence import write_voxels
    from voxpose.voxels.settings import VoxelSettings

    cfg = parse_params(args.params, schema=section("voxels", required=False))
    spec = parse_params(args.degradation, "--degradation", DEGRADATION)
    motion, rig = read_motion(args.motion), load_rig(args.rig)
    degradation = Degradation(spec["kind"], spec["level"], args.seed, spec.get("band_px", 2))
    settings = VoxelSettings.from_config(cfg, "--params")
    min_views = spec.get("min_views", settings.min_views)
    seq = voxelize_degraded(
        motion, rig, degradation, proportions=settings.proportions or None, follow_subject=settings.follow_subject,
        variation=settings.body_variation(motion.name, args.seed),
        seed=args.seed, **(settings.carving() | {"min_views": min_views}),
    )  # fmt: skip
    meta = voxel_meta(rig, args.rig, cfg, motion.name) | {"degradation": spec, "min_views": min_views}
    meta |= {"motion": motion.name, "kind": motion.kind, "fps": motion.fps}
    write_voxels(args.output, seq, meta, angles=motion.angles)
    log_counts(motion.name, seq)
