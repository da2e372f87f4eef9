"""Reading a user's text file (rig, calibration): an unreadable file is one error naming it and what it is."""

from pathlib import Path

from voxpose.errors import VoxposeError


def read_text(path, what: str) -> str:
    """The text of ``path``; ``what`` names the kind of file in the error (e.g. "rig file")."""
    try:
        return Path(path).read_text(encoding="utf-8")
    except OSError as err:
        raise VoxposeError(f"{path}: cannot read {what} ({err.strerror or err})") from None
    except UnicodeDecodeError:
        raise VoxposeError(f"{path}: not a valid {what} (not UTF-8 text)") from None
