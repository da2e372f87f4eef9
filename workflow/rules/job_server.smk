# The job server (voxpose.cli.job_server, issue 22): on a local run, the rules' `voxpose` commands run in forks of
# one process that has already imported voxpose, numpy, h5py and numba, instead of each paying that start-up. It
# starts with the jobs and stops with the run; cluster executors run jobs on other machines and never start it.
# `--config job_server=False` turns it off.

from voxpose.cli import job_server

_JOB_SERVER = []  # the running server's handle, when there is one


onstart:
    if config["job_server"] and workflow.local_exec and not workflow.remote_exec:
        handle = job_server.start("results/logs/job_server.log")
        if handle is not None:
            _JOB_SERVER.append(handle)


def _stop_job_server():
    while _JOB_SERVER:
        job_server.stop(_JOB_SERVER.pop())


onsuccess:
    _stop_job_server()


onerror:
    _stop_job_server()
