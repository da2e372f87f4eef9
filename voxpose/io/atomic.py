"""Atomic writes: every output appears complete or not at all.

Every file is written to a temporary name beside its target and renamed into place only when complete,
so an interrupted or failed job never leaves a partial output behind. A job killed outright (SIGKILL, a
cluster's time limit) cannot delete its temporary file; the next write of the same target does.
"""

import contextlib
import os
import re
import tempfile
from pathlib import Path


def _remove_stale(path: Path) -> None:
    """Delete the temporary files an earlier, killed write of ``path`` left (``.NAME.XXXXXXXX.tmp``, mkstemp's
    8 random characters): the rerun of a rule replaces them, so an interruption leaves nothing for good."""
    stale = re.compile(rf"\.{re.escape(path.name)}\.[a-z0-9_]{{8}}\.tmp")
    for entry in os.scandir(path.parent):
        if stale.fullmatch(entry.name) and entry.is_file(follow_symlinks=False):
            Path(entry.path).unlink(missing_ok=True)


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; rename it to ``path`` on success, delete it on error.

    Temporary files of ``path`` left by a killed earlier write are deleted first (one writer per target,
    as in the workflow).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    _remove_stale(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp = Path(tmp)
    try:
        yield tmp
        umask = os.umask(0)
        os.umask(umask)
        tmp.chmod(0o666 & ~umask)  # mkstemp creates 0600; give the file the usual permissions
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
