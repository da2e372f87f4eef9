"""``voxpose <subcommand>``: what the workflow's rules call, and what users run on their own data.

Each subcommand reads its inputs, calls the library and writes its outputs atomically. A user mistake
(``VoxposeError``) prints ``voxpose: error: <one line>`` and exits with status 2; progress goes to the log
(``--log FILE``) and to stderr.
"""

import argparse
import logging
import os
import sys

from voxpose.errors import VoxposeError

log = logging.getLogger("voxpose")

# A rule's `threads` bound BLAS/OpenMP threads too: on 2 cores, oversubscribed BLAS threads made small
# matrix products many times slower in our measurements.
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def _setup_logging(log_file) -> None:
    handlers = [logging.StreamHandler(sys.stderr)]
    if log_file:
        handlers.append(logging.FileHandler(log_file, mode="w"))
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s: %(message)s", handlers=handlers, force=True)


# Modules that define subcommands, each with a ``COMMANDS`` dict {name: (help, add_arguments, run)}.
COMMAND_MODULES = ("pipeline", "model", "claims")


def _commands():
    import importlib

    merged = {}
    for name in COMMAND_MODULES:
        commands = importlib.import_module(f".{name}", __package__).COMMANDS
        clash = sorted(set(commands) & set(merged))
        if clash:  # a programming error, caught by the CLI tests
            raise RuntimeError(f"voxpose.{name} redefines subcommand(s) {', '.join(clash)}")
        merged.update(commands)
    return merged


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="voxpose", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, (help_text, add_arguments, _) in _commands().items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        add_arguments(p)
        p.add_argument("--log", help="also write progress to this file")
        p.add_argument("--threads", type=int, default=1, help="threads for numerical libraries (default 1)")
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    for var in THREAD_VARIABLES:  # before numpy is imported: BLAS reads them once
        os.environ.setdefault(var, str(max(1, args.threads)))
    _setup_logging(args.log)
    run = _commands()[args.command][2]
    try:
        run(args)
    except VoxposeError as err:
        root = logging.getLogger()
        for handler in [h for h in root.handlers if type(h) is logging.StreamHandler]:
            root.removeHandler(handler)  # the error goes to stderr once, in the documented form
        root.addHandler(logging.NullHandler())
        log.error("error: %s", err)
        print(f"voxpose: error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
