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

from voxpose.errors import VoxposeError


def check_target(path) -> None:
    """A ``VoxposeError`` naming ``path`` when no file can be written there: it is a folder, or one of the
    folders it would be in is a file (checked before any work, by ``voxpose.cli.main``, and on writing)."""
    path = Path(path)
    if path.is_dir():
        raise VoxposeError(f"{path}: is a folder; give the name of the file to write")
    for parent in path.parents:
        if parent.exists():
            if not parent.is_dir():
                raise VoxposeError(f"{path}: cannot create folder {parent}: a file of that name is in the way")
            return


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
    check_target(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        _remove_stale(path)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as err:
        raise VoxposeError(f"{path}: cannot write here: {err.strerror or err}") from None
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
