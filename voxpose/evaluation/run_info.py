"""What the report's summary says about the run itself: a hash of its configuration, its wall time and the
software that made it. (The verify branch writes fuller provenance beside each table; this is the summary's part.)
"""

import hashlib
import json
import platform
import subprocess
import time
from importlib import metadata
from pathlib import Path

PACKAGES = ("voxpose", "snakemake", "numpy", "scipy", "h5py", "pandas", "matplotlib")


def config_hash(config: dict) -> str:
    """First 12 hex digits of the SHA-256 of the configuration as canonical JSON (keys sorted)."""
    return hashlib.sha256(json.dumps(config, sort_keys=True).encode()).hexdigest()[:12]


def versions() -> dict:
    """Python and each package's installed version ('not installed' where missing)."""
    out = {"python": platform.python_version()}
    for name in PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def commit(repo) -> str:
    """The repository's commit (with ``+changes`` if the tree differs), or 'unknown' outside git."""
    try:
        head = subprocess.run(
            ["git", "-C", str(repo), "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "-C", str(repo), "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return head + ("+changes" if dirty else "")


def wall_time_s(log_dir) -> float:
    """Seconds from the oldest job log in ``log_dir`` (the run's first job) to now: the run's wall time when the
    results were made in one run; after partial reruns, the time since the first job of the first one."""
    logs = [p.stat().st_mtime for p in Path(log_dir).rglob("*.log")]
    return time.time() - min(logs) if logs else float("nan")
