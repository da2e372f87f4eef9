"""The one exception type for user mistakes (bad files, bad config, bad arguments).

The CLI turns a ``VoxposeError`` into ``voxpose: error: <message>`` and exit code 2, so a user never
sees a traceback for a mistake of theirs. Messages name the file, line or key at fault.
"""


class VoxposeError(Exception):
    """A user-facing error; ``str(err)`` is the one-line message."""
