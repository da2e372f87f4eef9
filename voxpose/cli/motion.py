"""``voxpose motion``: a BVH file -> the 42 canonical joint angles per frame (Section 2)."""

import logging

from voxpose.cli.common import add_output, parse_params
from voxpose.config_schema import section

log = logging.getLogger("voxpose")

NAME = "motion"
HELP = "BVH -> canonical 42-angle poses (HDF5)"


def add_arguments(p):
    p.add_argument("bvh", help="BVH file")
    p.add_argument("--params", default="{}", help="JSON: the config's `motions` section")
    add_output(p)


def run(args):
    from voxpose.motion.data import write_motion
    from voxpose.motion.load import load_motion

    cfg = parse_params(args.params, schema=section("motions", required=False, drop=("overrides",)))
    motion = load_motion(
        args.bvh,
        fps=cfg.get("fps", 30.0),
        unit_scale=cfg.get("unit_scale"),
        joint_map=cfg.get("joint_map"),
        drop_reference_frame=cfg.get("drop_reference_frame", "auto"),
    )
    write_motion(args.output, motion)
    log.info("%s: %d frames at %g fps, height %.2f m", motion.name, motion.n_frames, motion.fps, motion.height)
