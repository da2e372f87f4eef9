# Before the `configfile:` directive reads config/config.yaml: a YAML error in it is one line naming the file and
# line (Snakemake's own message names neither). The --configfile files are read by Snakemake before the workflow
# starts; `voxpose check-config FILE...` names the file and line for those.

import os
import sys

from voxpose.config_schema import load_yaml
from voxpose.errors import VoxposeError

try:
    load_yaml(os.path.relpath(os.path.join(workflow.basedir, "config", "config.yaml")))
except VoxposeError as err:
    print(f"voxpose: error: {err}", file=sys.stderr)
    sys.exit(2)
