"""``voxpose derive``: a spiral or drunken walk, or a turned copy, derived from a real motion (BVH)."""

import json
import logging
from pathlib import Path

from voxpose.cli.common import add_output, parse_params, seed
from voxpose.config_schema import config_schema
from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

_LENGTH = {"type": "number", "exclusiveMinimum": 0}
_ANGLE = {"type": "number", "minimum": 0}
_UNIT = {"type": ["number", "null"], "exclusiveMinimum": 0}  # metres per file unit; null: inferred
# one schema per kind: the keyword arguments of its transform (voxpose.motion.derive); a turn's degrees as in the
# config's `derived` items (_schema)
SCHEMAS = {
    "spiral": {"type": "object", "additionalProperties": False,
               "properties": {"turns": {"type": ["number", "null"], "exclusiveMinimum": 0}, "r_start": _LENGTH,
                              "r_end": _LENGTH, "lean": {"type": "boolean"}, "unit": _UNIT}},
    "drunk": {"type": "object", "additionalProperties": False,
              "properties": {"wander": _ANGLE, "sway": {"type": "number", "minimum": 0}, "torso_roll": _ANGLE,
                             "torso_pitch": _ANGLE, "unit": _UNIT}},
}  # fmt: skip


def _schema(kind: str) -> dict:
    if kind != "turn":
        return SCHEMAS[kind]
    degrees = config_schema()["properties"]["derived"]["items"]["properties"]["degrees"]
    return {"type": "object", "additionalProperties": False, "required": ["degrees"],
            "properties": {"degrees": degrees}}  # fmt: skip


NAME = "derive"
HELP = "derive a spiral or drunken walk, or a turned copy, from a real motion (BVH)"


def add_arguments(p):
    p.add_argument("source", help="a real motion (BVH): a straight walk for spiral and drunk")
    p.add_argument("--kind", required=True, choices=["spiral", "drunk", "turn"])
    p.add_argument("--seed", type=seed, required=True)
    p.add_argument("--params", default="{}", help='JSON: transform parameters, e.g. {"degrees": 180} for turn')
    add_output(p)


def run(args):
    from voxpose.motion.derive import derive_file, derived_name

    out = Path(args.output)
    params = parse_params(args.params, schema=_schema(args.kind))
    expected = f"{derived_name(args.kind, Path(args.source).stem, params)}.bvh"
    if out.name != expected:
        raise VoxposeError(f"-o {out}: a derived {args.kind} motion of {args.source} must be named {expected}")
    _, provenance = derive_file(args.source, args.kind, out.parent, args.seed, params)
    log.info("derived %s: %s", out, json.dumps(provenance))
