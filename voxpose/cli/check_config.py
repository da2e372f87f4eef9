"""``voxpose check-config``: config files checked as the workflow would check them, naming file and line.

Snakemake reads ``--configfile`` files itself, before the workflow starts, and reports one that is not valid
YAML as "Config file is not valid JSON or YAML", without its name or line; this command names both, and
checks the merged config against the schema as the workflow does (``voxpose.config_schema``).
"""

import logging

from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

NAME = "check-config"
HELP = "check config files (YAML errors by file and line, values by key) as `snakemake --configfile` merges them"


def add_arguments(p):
    p.add_argument("configfiles", nargs="*", metavar="FILE", help="override files, merged in order")
    p.add_argument("--base", default="config/config.yaml", help="the workflow's config (default config/config.yaml)")


def run(args):
    from voxpose.config_schema import load_yaml, merge
    from voxpose.workflow_config import validate_config

    config = {}
    for path in (args.base, *args.configfiles):
        content = load_yaml(path)
        if content is None:
            continue
        if not isinstance(content, dict):
            raise VoxposeError(f"{path}: expected a mapping of config keys at the top level")
        config = merge(config, content)
    validate_config(config)
    log.info("config ok: %s", ", ".join((args.base, *args.configfiles)))
