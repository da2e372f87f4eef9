"""``voxpose serve``: the job server (``voxpose.cli.job_server``) on a Unix socket, until SIGTERM or until the
process that started it is gone. The workflow starts one for a local run; commands find it through
``VOXPOSE_SERVER``."""

NAME = "serve"
HELP = "run voxpose commands in forks of one process that has imported everything (the workflow starts it)"


def add_arguments(p):
    p.add_argument("--socket", required=True, help="path of the Unix socket to listen on")


def run(args):
    import logging
    import time

    from voxpose.cli import job_server
    from voxpose.cli.process import run_here

    start = time.monotonic()
    job_server.preload()
    logging.getLogger("voxpose").info("preloaded in %.2f s", time.monotonic() - start)
    job_server.serve(args.socket, run_here)
