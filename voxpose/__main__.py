"""``python -m voxpose``: the same as the ``voxpose`` command."""

import sys

from .cli import main

sys.exit(main())
