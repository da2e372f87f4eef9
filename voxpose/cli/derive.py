"""``voxpose derive``: a spiral or drunken walk, or a turned copy, derived from a real motion (BVH)."""

import json
import logging
from pathlib import Path

from voxpose.cli.common import add_output, parse_params
from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

NAME = "derive"
HELP = "derive a spiral or drunken walk, or a turned copy, from a real motion (BVH)"


def add_arguments(p):
    p.add_argument("source", help="a real motion (BVH): a straight walk for spiral and drunk")
    p.add_argument("--kind", required=True, choices=["spiral", "drunk", "turn"])
    p.add_argument("--seed", type=int, required=True)
    p.add_argument("--params", default="{}", help='JSON: transform parameters, e.g. {"degrees": 180} for turn')
    add_output(p)


def run(args):
    from voxpose.motion.derive import derive_file, derived_name

    out = Path(args.output)
    params = parse_params(args.params)
    expected = f"{derived_name(args.kind, Path(args.source).stem, params)}.bvh"
    if out.name != expected:
        raise VoxposeError(f"-o {out}: a derived {args.kind} motion of {args.source} must be named {expected}")
    _, provenance = derive_file(args.source, args.kind, out.parent, args.seed, params)
    log.info("derived %s: %s", out, json.dumps(provenance))
