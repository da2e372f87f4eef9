"""``voxpose <subcommand>``: what the workflow's rules call, and what users run on their own data.

Each subcommand reads its inputs, calls the library and writes its outputs atomically. A user mistake
(``VoxposeError``) prints ``voxpose: error: <one line>`` and exits with status 2; progress goes to the log
(``--log FILE``) and to stderr.
"""

import argparse
import importlib
import logging
import os
import sys
from dataclasses import dataclass
from pathlib import Path

from voxpose.cli.common import positive_integer
from voxpose.errors import VoxposeError
from voxpose.io.atomic import check_target

log = logging.getLogger("voxpose")

# A rule's `threads` bound BLAS/OpenMP threads too: on 2 cores, oversubscribed BLAS threads made small
# matrix products many times slower in our measurements. BLAS reads them once, when numpy is first imported,
# so `main` sets them before it imports any subcommand (Snakemake sets them for its jobs as well).
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def _setup_logging(log_file) -> None:
    """Progress to stderr and, with ``--log``, to that file (its folder made, as an output's is)."""
    handlers = [logging.StreamHandler(sys.stderr)]
    if log_file:
        try:
            Path(log_file).parent.mkdir(parents=True, exist_ok=True)
            handlers.append(logging.FileHandler(log_file, mode="w"))
        except OSError as err:
            raise VoxposeError(f"--log {log_file}: cannot write it ({err.strerror})") from None
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s: %(message)s", handlers=handlers, force=True)


@dataclass(frozen=True)
class Subcommand:
    """One ``voxpose`` subcommand: its defining module, imported only when the subcommand is run (or the whole
    list is shown), the name of its entry point there, and its help line (None: the module's ``HELP``).

    ``module`` is what a workflow rule's code hash covers (the import closure of that module,
    ``voxpose.import_graph``): one module per subcommand, so a rule reruns for exactly the code it runs.
    """

    module: str
    entry: str = "run"
    help: str | None = None

    def load(self):
        """(help, add_arguments, run) of the subcommand, importing its module."""
        module = importlib.import_module(self.module)
        return self.help or module.HELP, module.add_arguments, getattr(module, self.entry)


# Each module voxpose.cli.<name> defines ``voxpose <name with - for _>`` (NAME, HELP, add_arguments, run).
_MODULES = ("generate", "derive", "motion", "rig", "voxelize", "carve", "describe", "fit_features", "features",
            "regress", "evaluate", "experiment_table", "generalisation_table", "table1", "table2", "paper_claims",
            "report_summary", "readme_tables", "figure4", "joint_errors", "error_over_time", "gallery",
            "voxelize_degraded", "silhouette_contexts", "fit_silhouette_features", "silhouette_features",
            "export_model", "predict", "render", "silhouettes", "data_fetch", "check_config", "verify",
            "serve")  # fmt: skip

SUBCOMMANDS = {name.replace("_", "-"): Subcommand(f"voxpose.cli.{name}") for name in _MODULES} | {
    "camera-figure": Subcommand("voxpose.cli.claims_figure", "run_cameras",
                                "error against camera rig: transferred, retrained, A&T"),
    "robustness-figure": Subcommand("voxpose.cli.claims_figure", "run_robustness",
                                    "error against silhouette degradation"),
}  # fmt: skip


def thread_defaults(argv) -> dict:
    """The thread variables ``main`` sets where they are unset: each to ``--threads`` in ``argv`` (default 1); none
    for a malformed value, which is left for the parser to refuse."""
    threads = "1"
    for i, word in enumerate(argv):
        if word == "--threads" and i + 1 < len(argv):
            threads = argv[i + 1]
        elif word.startswith("--threads="):
            threads = word.split("=", 1)[1]
    return dict.fromkeys(THREAD_VARIABLES, threads) if threads.isdigit() and int(threads) >= 1 else {}


class _Parser(argparse.ArgumentParser):
    """argparse with the documented error form: one line ``voxpose: error: <command>: ...``, exit status 2."""

    def error(self, message):
        command = self.prog.removeprefix("voxpose").strip()
        self.exit(2, f"voxpose: error: {command + ': ' if command else ''}{message}\n")


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The ``voxpose`` parser with every subcommand, or with subcommand ``only`` alone (importing only its module)."""
    parser = _Parser(prog="voxpose", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, command in SUBCOMMANDS.items():
        if only is not None and name != only:
            continue
        help_line, add_arguments, _ = command.load()
        p = sub.add_parser(name, help=help_line, description=help_line)
        add_arguments(p)
        p.add_argument("--log", help="also write progress to this file")
        p.add_argument(
            "--threads", type=positive_integer, default=1, help="threads for numerical libraries (default 1)"
        )
    return parser


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    for name, value in thread_defaults(argv).items():  # before any subcommand's module imports numpy
        os.environ.setdefault(name, value)
    parser = build_parser(argv[0] if argv and argv[0] in SUBCOMMANDS else None)
    args = parser.parse_args(argv)
    try:
        _setup_logging(args.log)
        run = SUBCOMMANDS[args.command].load()[2]
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
        # one write, newline included: jobs running side by side share Snakemake's stderr, and with unbuffered
        # streams (PYTHONUNBUFFERED) print() writes the newline separately, so two jobs' lines could interleave
        sys.stderr.write(f"voxpose: error: {err}\n")
        return 2
    return status or 0


if __name__ == "__main__":
    sys.exit(main())
