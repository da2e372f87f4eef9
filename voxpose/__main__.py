"""``python -m voxpose``: the same as the ``voxpose`` command."""

import sys

from voxpose.cli.main import main

sys.exit(main())
