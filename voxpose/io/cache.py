"""The workflow's HDF5 caches under ``results/``: which are damaged (``voxpose.io.checksum``) and which rule makes
each, so that ``voxpose verify --remove`` can delete exactly those for Snakemake to make again."""

import contextlib
import os
from pathlib import Path

from voxpose.io.hdf5 import file_damage


def damaged_caches(results) -> list[tuple[Path, str]]:
    """(path, reason) of every ``*.h5`` file under ``results`` that fails its checksum, sorted by path."""
    found = []
    for path in sorted(Path(results).rglob("*.h5")):
        reason = file_damage(path)
        if reason is not None:
            found.append((path, reason))
    return found


@contextlib.contextmanager
def _restored():
    """The working directory and environment as they were: loading a workflow changes both (the Snakefile may set
    variables for its jobs), and the caller's process must not inherit them."""
    cwd, environ = Path.cwd(), dict(os.environ)
    try:
        yield
    finally:
        os.chdir(cwd)
        os.environ.clear()
        os.environ.update(environ)


def producing_rules(paths, workdir) -> dict:
    """{path: name of the workflow rule whose output pattern matches it, or None} for the Snakefile in ``workdir``.

    The rules are read from the workflow itself (Snakemake's API, the Snakefile's own config), so the answer
    follows the workflow as it is; a file no rule makes maps to None."""
    from snakemake.api import SnakemakeApi
    from snakemake.settings.types import OutputSettings, Quietness, ResourceSettings

    workdir = Path(workdir).resolve()
    relative = {p: os.path.relpath(Path(p).resolve(), workdir) for p in paths}
    with _restored(), SnakemakeApi(OutputSettings(quiet={Quietness.ALL})) as api:
        workflow = api.workflow(resource_settings=ResourceSettings(), snakefile=workdir / "Snakefile",
                                workdir=workdir)._workflow  # fmt: skip
        rules = list(workflow.rules)
        return {p: next((r.name for r in rules if r.is_producer(rel)), None) for p, rel in relative.items()}
