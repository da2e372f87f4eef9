"""``python -m voxpose``: the same as the ``voxpose`` command."""

from voxpose.cli.process import run

run()
