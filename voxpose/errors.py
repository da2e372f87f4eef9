"""The one exception type for user mistakes (bad files, bad config, bad arguments).

The CLI turns a ``VoxposeError`` into ``voxpose: error: <message>`` and exit code 2, so a user never
sees a traceback for a mistake of theirs. Messages name the file, line or key at fault.
"""


class VoxposeError(Exception):
    """A user-facing error; ``str(err)`` is the one-line message."""


class NotFittedError(VoxposeError):
    """An estimator used before ``fit`` (or ``from_arrays``): ``str(err)`` names its class."""


class ConvergenceWarning(UserWarning):
    """An iterative fit stopped at ``max_iter`` before its convergence test held; its result is usable, but
    more iterations (or a looser ``tol``) would change it."""
