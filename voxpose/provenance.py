"""Provenance of a result: the voxpose version, the git commit of the workflow's checkout, the Python and key
package versions, and the hash of the config that made it, written as ``<table>.meta.json`` beside every table
under ``results/tables`` (JSON, so that the CSV stays a plain table for any reader)."""

import hashlib
import json
import platform
import subprocess
from importlib import metadata
from pathlib import Path

from voxpose import __version__
from voxpose.io.atomic import atomic_path

# The packages whose versions can change a number in a table (and Snakemake, which decides what reruns).
KEY_PACKAGES = ("numpy", "scipy", "h5py", "pandas", "matplotlib", "snakemake")
NOT_GIT = "not a git checkout"


def config_hash(config: dict) -> str:
    """``sha256:<hex>`` of the config as canonical JSON (keys sorted): equal configs hash equally, whatever the
    order of their keys or the files they were merged from."""
    text = json.dumps(config, sort_keys=True, separators=(",", ":"), default=str)
    return "sha256:" + hashlib.sha256(text.encode()).hexdigest()


def git_commit(directory=".") -> str:
    """The commit checked out in ``directory``, with ``+modified`` when tracked files differ from it, or
    ``NOT_GIT`` (no git, or not inside a repository)."""
    def git(*args):
        return subprocess.run(["git", "-C", str(directory), *args], capture_output=True, text=True, check=True).stdout

    try:
        commit = git("rev-parse", "HEAD").strip()
        modified = git("status", "--porcelain", "--untracked-files=no").strip()
    except (OSError, subprocess.CalledProcessError):
        return NOT_GIT
    return f"{commit}+modified" if modified else commit


def _version(package: str) -> str:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "not installed"


def provenance(config_hash_: str | None, directory=".") -> dict:
    """What made a result: ``config_hash_`` is None for a command run by hand, outside the workflow."""
    return {
        "voxpose": __version__,
        "git_commit": git_commit(directory),
        "python": platform.python_version(),
        "packages": {name: _version(name) for name in KEY_PACKAGES},
        "config_hash": config_hash_ or "none (run outside the workflow)",
    }


def meta_path(table) -> Path:
    """``results/tables/table1.csv`` -> ``results/tables/table1.meta.json``."""
    table = Path(table)
    return table.with_name(f"{table.stem}.meta.json")


def write_meta(table, config_hash_: str | None) -> None:
    """The provenance of ``table``, written atomically beside it."""
    with atomic_path(meta_path(table)) as tmp:
        tmp.write_text(json.dumps(provenance(config_hash_), indent=2, sort_keys=True) + "\n")
