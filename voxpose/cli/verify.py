"""``voxpose verify``: find the damaged HDF5 caches of a workflow's results (content checksums) and the rule that
makes each; ``--remove`` deletes them and prints the ``snakemake --forcerun FILE...`` that makes exactly those again
and everything made from them (a plain ``snakemake`` does not remake a missing intermediate file whose dependants
are up to date: it makes it again only when a job needs it)."""

import os
import shlex
from pathlib import Path

from voxpose.errors import VoxposeError

NAME = "verify"
HELP = "list damaged cache files (checksums) and the rules that make them; --remove deletes them"


def add_arguments(p):
    p.add_argument("results", nargs="?", default="results", help="the workflow's results folder (default results)")
    p.add_argument("--remove", action="store_true", help="delete the damaged files and print the snakemake command "
                   "that makes them and their dependants again")  # fmt: skip


def run(args):
    from voxpose.io.cache import damaged_caches, producing_rules

    results = Path(args.results)
    if not results.is_dir():
        raise VoxposeError(f"{results}: no such folder")
    damaged = damaged_caches(results)
    workdir = results.resolve().parent
    rules = producing_rules([p for p, _ in damaged], workdir) if damaged and (workdir / "Snakefile").is_file() else {}
    for path, reason in damaged:
        rule = rules.get(path)
        print(f"{path}: {reason} (made by rule {rule})" if rule else f"{path}: {reason} (made by no rule)")
    if not damaged:
        print(f"{results}: every cache file matches its checksum")
        return 0
    if not args.remove:
        print(f"{len(damaged)} damaged; `voxpose verify --remove {results}` deletes them, then run snakemake")
        return 1
    for path, _ in damaged:
        path.unlink()
    again = " ".join(shlex.quote(os.path.relpath(path.resolve(), workdir)) for path, _ in damaged)
    print(f"removed {len(damaged)} damaged files; in {workdir}, this makes them and everything made from them "
          f"again (with your usual options): snakemake --forcerun {again}")  # fmt: skip
    return 0
