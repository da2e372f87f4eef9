"""How long the run behind the report took (its summary page; the rest of what made it is
``voxpose.provenance``)."""

import time
from pathlib import Path


def wall_time_s(log_dir) -> float:
    """Seconds from the oldest job log in ``log_dir`` (the run's first job) to now: the run's wall time when the
    results were made in one run; after partial reruns, the time since the first job of the first one."""
    logs = [p.stat().st_mtime for p in Path(log_dir).rglob("*.log")]
    return time.time() - min(logs) if logs else float("nan")
