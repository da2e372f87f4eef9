"""``voxpose rig``: the calibration file of the configured camera rig (Section 6: cameras on a circle)."""

import logging

from voxpose.cli.common import add_output, parse_params
from voxpose.config_schema import section

log = logging.getLogger("voxpose")

NAME = "rig"
HELP = "write the calibration file of the configured camera rig"


def add_arguments(p):
    p.add_argument("--params", required=True, help="JSON: the config's `rig` section")
    add_output(p)


def run(args):
    from voxpose.voxels.cameras import rig_from_config, save_rig

    rig = rig_from_config(parse_params(args.params, schema=section("rig")))
    save_rig(rig, args.output)
    log.info("rig %s: %d cameras -> %s", rig.name, len(rig), args.output)
