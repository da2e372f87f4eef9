"""``voxpose <subcommand>``: what the workflow's rules call, and what users run on their own data.

Each subcommand reads its inputs, calls the library and writes its outputs atomically. A user mistake
(``VoxposeError``) prints ``voxpose: error: <one line>`` and exits with status 2; progress goes to the log
(``--log FILE``) and to stderr.
"""

import argparse
import logging
import os
import sys
from collections.abc import Callable
from dataclasses import dataclass

from voxpose.cli import (
    carve,
    check_config,
    claims_figure,
    data_fetch,
    derive,
    describe,
    error_over_time,
    evaluate,
    experiment_table,
    export_model,
    features,
    figure4,
    fit_features,
    fit_silhouette_features,
    gallery,
    generalisation_table,
    generate,
    joint_errors,
    motion,
    paper_claims,
    predict,
    readme_tables,
    regress,
    render,
    report_summary,
    rig,
    silhouette_contexts,
    silhouette_features,
    silhouettes,
    table1,
    table2,
    verify,
    voxelize,
    voxelize_degraded,
)
from voxpose.cli.common import positive_integer
from voxpose.errors import VoxposeError
from voxpose.io.atomic import check_target

log = logging.getLogger("voxpose")

# A rule's `threads` bound BLAS/OpenMP threads too: on 2 cores, oversubscribed BLAS threads made small
# matrix products many times slower in our measurements.
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def _setup_logging(log_file) -> None:
    handlers = [logging.StreamHandler(sys.stderr)]
    if log_file:
        handlers.append(logging.FileHandler(log_file, mode="w"))
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s: %(message)s", handlers=handlers, force=True)


@dataclass(frozen=True)
class Subcommand:
    """One ``voxpose`` subcommand: its help line, argument builder, entry point and defining module.

    ``module`` is what a workflow rule's code hash covers (the import closure of that module,
    ``voxpose.import_graph``): one module per subcommand, so a rule reruns for exactly the code it runs.
    """

    help: str
    add_arguments: Callable
    run: Callable
    module: str


def _of(module) -> tuple[str, Subcommand]:
    return module.NAME, Subcommand(module.HELP, module.add_arguments, module.run, module.__name__)


SUBCOMMANDS = dict(
    map(_of, (generate, derive, motion, rig, voxelize, carve, describe, fit_features, features, regress, evaluate,
              experiment_table, generalisation_table, table1, table2, paper_claims, report_summary, readme_tables,
              figure4, joint_errors, error_over_time, gallery, voxelize_degraded, silhouette_contexts,
              fit_silhouette_features, silhouette_features, export_model, predict, render, silhouettes, data_fetch,
              check_config, verify))
) | {  # fmt: skip
    "camera-figure": Subcommand("error against camera rig: transferred, retrained, A&T", claims_figure.add_arguments,
                                claims_figure.run_cameras, claims_figure.__name__),
    "robustness-figure": Subcommand("error against silhouette degradation", claims_figure.add_arguments,
                                    claims_figure.run_robustness, claims_figure.__name__),
}  # fmt: skip


class _Parser(argparse.ArgumentParser):
    """argparse with the documented error form: one line ``voxpose: error: <command>: ...``, exit status 2."""

    def error(self, message):
        command = self.prog.removeprefix("voxpose").strip()
        self.exit(2, f"voxpose: error: {command + ': ' if command else ''}{message}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="voxpose", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, command in SUBCOMMANDS.items():
        p = sub.add_parser(name, help=command.help, description=command.help)
        command.add_arguments(p)
        p.add_argument("--log", help="also write progress to this file")
        p.add_argument(
            "--threads", type=positive_integer, default=1, help="threads for numerical libraries (default 1)"
        )
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    for var in THREAD_VARIABLES:  # before numpy is imported: BLAS reads them once
        os.environ.setdefault(var, str(args.threads))
    _setup_logging(args.log)
    run = SUBCOMMANDS[args.command].run
    try:
        for option in ("output", "csv", "md", "png", "pdf", "record", "predictions", "angles"):
            target = getattr(args, option, None)
            if isinstance(target, str):  # an output: before any work, a folder or a file in the way is a mistake
                check_target(target)
        status = run(args)  # None: success; a check (``verify``) may return 1 for what it found
    except VoxposeError as err:
        root = logging.getLogger()
        for handler in [h for h in root.handlers if type(h) is logging.StreamHandler]:
            root.removeHandler(handler)  # the error goes to stderr once, in the documented form
        root.addHandler(logging.NullHandler())
        log.error("error: %s", err)
        print(f"voxpose: error: {err}", file=sys.stderr)
        return 2
    return status or 0


if __name__ == "__main__":
    sys.exit(main())
