"""Argument helpers shared by the subcommands: JSON parameters checked by a schema, number arguments checked
as they are parsed, the output option, voxel-file provenance.

Every parameter is checked at the edge, before any work (issue 21): ``--params`` by the schema of the config
section whose keys it takes (``voxpose.config_schema.section``), numbers by the ``argparse`` types below, so a
mistake is one ``voxpose: error:`` line naming the option, never a traceback or a silent default.
"""

import argparse
import json
import logging
import math
import os
from pathlib import Path

from voxpose.config_schema import validate
from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

# the workflow (workflow/rules/common.smk) puts its config hash here for the table commands
CONFIG_HASH_VARIABLE = "VOXPOSE_CONFIG_HASH"


def parse_json(text: str, what: str, schema: dict | None = None):
    """``text`` as JSON (checked by ``schema`` when given), else a ``VoxposeError`` naming the option ``what``."""
    try:
        value = json.loads(text)
    except json.JSONDecodeError as err:
        raise VoxposeError(f"{what}: not valid JSON ({err})") from None
    if schema is not None:
        validate(value, schema, what)
    return value


def list_of(item: dict) -> dict:
    """Schema of a non-empty JSON list of ``item`` (the workflow's ``--runs``)."""
    return {"type": "array", "minItems": 1, "items": item}


def row(*types) -> dict:
    """Schema of a JSON list of exactly ``len(types)`` values of these JSON types, e.g. ``row("string", "string")``."""
    return {"type": "array", "minItems": len(types), "maxItems": len(types),
            "prefixItems": [{"type": t} for t in types]}  # fmt: skip


def record(*keys: str) -> dict:
    """Schema of a JSON object with (at least) these keys."""
    return {"type": "object", "required": list(keys)}


def parse_params(text: str, what: str = "--params", schema: dict | None = None) -> dict:
    """A JSON object of parameters, checked by ``schema`` when given (number-like strings become numbers)."""
    value = parse_json(text, what)
    if not isinstance(value, dict):
        raise VoxposeError(f"{what}: expected a JSON object")
    if schema is not None:
        validate(value, schema, what)
    return value


def finite_number(text: str) -> float:
    """argparse type: any finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return value


def positive_number(text: str) -> float:
    """argparse type: a finite number > 0."""
    value = finite_number(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text}")
    return value


def non_negative_number(text: str) -> float:
    """argparse type: a finite number >= 0."""
    value = finite_number(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be a number >= 0, got {text}")
    return value


def _integer(text: str, minimum: int) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < minimum:
        raise argparse.ArgumentTypeError(f"must be a whole number >= {minimum}, got {text}")
    return value


def positive_integer(text: str) -> int:
    """argparse type: a whole number >= 1."""
    return _integer(text, 1)


def non_negative_integer(text: str) -> int:
    """argparse type: a whole number >= 0 (an index; a seed, as numpy refuses negative seeds)."""
    return _integer(text, 0)


seed = non_negative_integer


def named_paths(pairs: list[str], option: str) -> list[tuple[str, str]]:
    """``NAME=PATH`` arguments as (name, path) pairs, else a ``VoxposeError`` naming the option."""
    out = []
    for pair in pairs:
        name, sep, path = pair.partition("=")
        if not (sep and name and path):
            raise VoxposeError(f"{option} {pair!r}: expected NAME=PATH")
        out.append((name, path))
    return out


def check_suffix(path, option: str, *suffixes: str) -> Path:
    """``path`` when its suffix is one of ``suffixes`` (any case), else a ``VoxposeError`` naming the format."""
    path = Path(path)
    if path.suffix.lower() not in suffixes:
        raise VoxposeError(f"{option} {path}: expected a {' or '.join(suffixes)} file")
    return path


def add_output(p):
    p.add_argument("-o", "--output", required=True, help="output file")


def add_table_csv(p):
    """``--csv`` of a table and ``--config-hash``: the table's provenance goes beside it (``voxpose.provenance``)."""
    p.add_argument("--csv", required=True, help="the table (CSV); its provenance is written beside it, NAME.meta.json")
    p.add_argument("--config-hash", default=os.environ.get(CONFIG_HASH_VARIABLE),
                   help=f"hash of the config that made the table (default: ${CONFIG_HASH_VARIABLE}, the workflow's)")


def write_table_meta(args) -> None:
    from voxpose.provenance import write_meta

    write_meta(args.csv, args.config_hash)


def voxel_meta(rig, rig_path, cfg, source: str) -> dict:
    """Provenance of a voxel file: the rig's calibration as given, the parameters, the source."""
    return {"source": source, "rig": rig.name, "rig_calibration": Path(rig_path).read_text(), "params": cfg}


def log_counts(name, seq):
    counts = seq.counts()
    log.info(
        "%s: %d frames, l_res %.4f m, h_sub %.3f m; mean voxels %.0f, surface %.0f, basis %.0f; %d empty",
        name, seq.n_frames, seq.l_res, seq.h_sub, counts["occupied"].mean(), counts["surface"].mean(),
        counts["basis"].mean(), int(seq.empty.sum()),
    )  # fmt: skip
