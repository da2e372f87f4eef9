"""``voxpose generate``: one motion of the embedded default set (Section 6's five types), written as BVH."""

import logging

from voxpose.cli.common import add_output, check_suffix, non_negative_integer, positive_integer, seed
from voxpose.config_schema import config_schema, validate

log = logging.getLogger("voxpose")

NAME = "generate"
HELP = "write one motion of the embedded default set as BVH"


def add_arguments(p):
    p.add_argument("--kind", required=True, choices=["walk", "drunk", "spiral", "jog", "jump"])
    p.add_argument("--index", type=non_negative_integer, required=True, help="sequence number within its kind")
    p.add_argument("--frames", type=positive_integer, required=True, help="as in the config's `generated` lists")
    p.add_argument("--seed", type=seed, required=True, help="master seed of the generated set")
    add_output(p)


def run(args):
    from voxpose.io.bvh import write_bvh
    from voxpose.motion.generate import default_motion

    validate(args.frames, config_schema()["$defs"]["frames"]["items"], "--frames")
    check_suffix(args.output, "-o", ".bvh")
    write_bvh(default_motion(args.kind, args.index, n_frames=args.frames, seed=args.seed), args.output)
    log.info("generated %s %d (%d frames, seed %d) -> %s", args.kind, args.index, args.frames, args.seed, args.output)
