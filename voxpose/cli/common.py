"""Argument helpers shared by the subcommands: JSON parameters, the output option, voxel-file provenance."""

import json
import logging
import os
from pathlib import Path

from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

# the workflow (workflow/rules/common.smk) puts its config hash here for the table commands
CONFIG_HASH_VARIABLE = "VOXPOSE_CONFIG_HASH"


def parse_params(text: str, what: str = "--params") -> dict:
    try:
        value = json.loads(text)
    except json.JSONDecodeError as err:
        raise VoxposeError(f"{what}: not valid JSON ({err})") from None
    if not isinstance(value, dict):
        raise VoxposeError(f"{what}: expected a JSON object")
    return value


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
