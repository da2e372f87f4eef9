"""The job server: ``voxpose`` commands run in forks of one process that has already imported everything
(issue 22).

Why: a workflow run starts about 400 ``voxpose`` processes, most of them a few seconds long, and each pays
the same start-up before its first line of work: the imports (numpy, h5py, jsonschema, the subcommand's
modules: about 0.2 s) and, in the ~270 that run a compiled kernel, numba's (its import and the target context
it refreshes before the first cached kernel loads, which imports scipy.linalg: about 0.45 s more). A fork of a
process that has done all that starts at the first line of work.

How: ``voxpose serve --socket PATH`` imports every voxpose module and numba's runtime once, then listens on a
Unix socket. The ``voxpose`` command (``voxpose.cli.process``), when the variable ``VOXPOSE_SERVER`` names a
socket, sends its arguments, working folder and environment, and its stdin, stdout and stderr (SCM_RIGHTS), and
waits. The server forks; the fork takes the request's folder, environment, streams and arguments and runs the
command as the process would have (``voxpose.cli.process.run_here``), and the server sends back its exit status,
which the command exits with. Same code, same inputs: the same outputs, bit for bit.

The command runs in its own process instead (always correct, only slower) when ``VOXPOSE_SERVER`` is unset,
when nothing answers on the socket (the server not started yet or gone; a cluster job on another machine), or
when the server refuses because its fork would not be the process the command would have started: another
interpreter or ``sys.path``, a variable read at start-up that differs (``STARTUP_VARIABLES``: numba's, the
thread counts Snakemake sets per job, Python's), or a voxpose source file changed since the server imported it.

Stopping: the command forwards SIGINT, SIGTERM and SIGHUP to its fork (those it ignores, the fork ignores), and
the server sends SIGTERM to a fork whose command went away (killed outright), so stopping a job stops its work as
before. The server exits on SIGTERM (terminating the forks still running) and when the process that started it
is gone. Each job is a line in the server's log: its pid, command, exit status and seconds.

Linux only (``os.pidfd_open``); elsewhere ``serve`` refuses and commands run in their own processes.
"""

import json
import logging
import os
import selectors
import signal
import socket
import struct
import sys
import time

ENV = "VOXPOSE_SERVER"
STARTUP_VARIABLES = ("PYTHON", "NUMBA_", "OMP_", "OPENBLAS_", "MKL_", "GOTO_", "VECLIB_", "NUMEXPR_", "HDF5_", "LD_")
FORWARDED = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
_HEADER = struct.Struct("!I")  # each message: its length, then that many bytes of JSON
_STREAMS = (0, 1, 2)
_REQUEST = {"argv", "cwd", "env", "executable", "path", "ignored"}

log = logging.getLogger("voxpose")


# -- the command's side: kept to the standard library, so that a served command imports nothing heavy --------


def run_remote(argv: list) -> int | None:
    """Run ``voxpose argv`` in a fork of the server named by ``VOXPOSE_SERVER`` and return its exit status;
    None when the command should run in this process (no server, no answer, or refused)."""
    path = os.environ.get(ENV)
    if not path:
        return None
    request = {
        "argv": list(argv),
        "cwd": os.getcwd(),
        "env": dict(os.environ),
        "executable": sys.executable,
        "path": sys.path,
        "ignored": [int(sig) for sig in FORWARDED if signal.getsignal(sig) == signal.SIG_IGN],
    }
    # the forwarded signals wait until the fork's pid is known and they can be passed on (a SIGINT in between
    # would kill this process and leave its fork running until the server noticed)
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, FORWARDED)
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        try:
            try:
                sock.connect(path)
                socket.send_fds(sock, [_frame(request)], list(_STREAMS))
                reply = _receive(sock)
            except OSError:
                return None
            if not reply or "pid" not in reply:
                return None  # refused: the reason is in the server's log
            pid = reply["pid"]
            for sig in set(FORWARDED) - set(request["ignored"]):  # what this process ignores, its fork ignores
                signal.signal(sig, lambda number, _frame, pid=pid: _signal(pid, number))
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        try:
            reply = _receive(sock)
        except OSError:
            reply = None
    if not reply or "status" not in reply:
        sys.stderr.write(f"voxpose: error: the job server at {path} stopped before the command ended\n")
        return 1
    return reply["status"]


def _signal(pid: int, number: int) -> None:
    try:
        os.kill(pid, number)
    except ProcessLookupError:
        pass


def _frame(message: dict) -> bytes:
    data = json.dumps(message).encode()
    return _HEADER.pack(len(data)) + data


def _read(sock, n: int, head: bytes = b"") -> bytes | None:
    """Exactly ``n`` bytes (``head`` already read among them), or None at end of stream."""
    data = bytearray(head)
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            return None
        data += chunk
    return bytes(data)


def _receive(sock, head: bytes = b"") -> dict | None:
    """One message, or None when the other side closed the connection first."""
    header = _read(sock, _HEADER.size, head[: _HEADER.size])
    if header is None:
        return None
    body = _read(sock, _HEADER.unpack(header)[0], head[_HEADER.size :])
    return None if body is None else json.loads(body)


# -- the server's side ---------------------------------------------------------------------------------------


class _Stop(Exception):
    """SIGTERM: stop serving."""


def serve(path: str, runner, parent: int | None = None) -> None:
    """Serve requests on a Unix socket at ``path`` until SIGTERM or until process ``parent`` (default: the one
    that started this one) is gone, running each in a fork as ``runner(argv) -> status``. Call it after
    ``preload``: what is imported here is what every fork starts with."""
    if not hasattr(os, "pidfd_open"):
        from voxpose.errors import VoxposeError

        raise VoxposeError("serve: needs Linux (os.pidfd_open); commands run in their own processes elsewhere")
    parent = os.getppid() if parent is None else parent
    sources = _source_times()
    startup = _startup(dict(os.environ))
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    staging = f"{path}.{os.getpid()}"
    listener.bind(staging)  # bound and listening before it takes its name: a client never finds a dead socket
    listener.listen(64)
    os.replace(staging, path)
    selector = selectors.DefaultSelector()
    selector.register(listener, selectors.EVENT_READ)
    jobs = {}  # pid -> _Job
    previous = signal.signal(signal.SIGTERM, _raise_stop)
    # SIGTERM is taken only while waiting, so that it never falls between a fork and its bookkeeping
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGTERM})
    log.info("serving on %s (pid %d)", path, os.getpid())
    try:
        while os.getppid() == parent:
            signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGTERM})
            events = selector.select(timeout=1.0)
            signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGTERM})
            for key, _ in events:
                if key.fileobj is listener:
                    _accept(listener, selector, jobs, runner, sources, startup)
                else:
                    key.data(selector, jobs)
    except _Stop:
        log.info("stopping: SIGTERM")
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        signal.signal(signal.SIGTERM, previous)
        for job in list(jobs.values()):
            _signal(job.pid, signal.SIGTERM)
            os.waitpid(job.pid, 0)
            job.close(selector)
        selector.close()
        listener.close()
        if os.path.exists(path):
            os.unlink(path)


def _raise_stop(_number, _frame):
    raise _Stop


class _Job:
    """A running fork: its pidfd tells when it ended, its command's connection when the command went away."""

    def __init__(self, pid: int, conn, argv: list, selector, jobs: dict):
        self.pid, self.conn, self.argv, self.start = pid, conn, argv, time.monotonic()
        self.pidfd = os.pidfd_open(pid)
        selector.register(self.pidfd, selectors.EVENT_READ, self.ended)
        selector.register(conn, selectors.EVENT_READ, self.gone)
        jobs[pid] = self

    def ended(self, selector, jobs):
        _, status = os.waitpid(self.pid, 0)
        code = os.waitstatus_to_exitcode(status)
        code = code if code >= 0 else 128 - code  # killed by signal n: 128 + n, as a shell reports it
        log.info("job %d: exit %d after %.2f s: voxpose %s", self.pid, code, time.monotonic() - self.start,
                 " ".join(self.argv))  # fmt: skip
        if self.conn is not None:
            try:
                self.conn.sendall(_frame({"status": code}))
            except OSError:
                pass
        del jobs[self.pid]
        self.close(selector)

    def gone(self, selector, jobs):
        """The command's end of the connection closed or sent something: it is gone; so goes its fork."""
        log.info("job %d: its command went away; terminating it", self.pid)
        _signal(self.pid, signal.SIGTERM)
        selector.unregister(self.conn)
        self.conn.close()
        self.conn = None

    def close(self, selector):
        selector.unregister(self.pidfd)
        os.close(self.pidfd)
        if self.conn is not None:
            selector.unregister(self.conn)
            self.conn.close()
            self.conn = None


def _accept(listener, selector, jobs, runner, sources, startup) -> None:
    """Read one request; refuse it, or fork it into a job."""
    conn, _ = listener.accept()
    conn.settimeout(10.0)  # a request is sent whole right after connecting
    fds = []
    try:
        data, fds, _, _ = socket.recv_fds(conn, 65536, len(_STREAMS))
        request = _receive(conn, data) if data else None
        reason = _refusal(request, fds, sources, startup)
        if reason:
            log.info("refused: %s", reason)
            conn.close()
            return
        conn.settimeout(None)
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:
            _close_inherited(listener, selector, jobs, conn)
            _child(request, fds, runner)  # never returns
    except (OSError, ValueError) as err:
        log.info("refused: %s", err)  # a broken request, or no fork: the command runs alone
        conn.close()
        return
    finally:
        for fd in fds:
            os.close(fd)
    job = _Job(pid, conn, request["argv"], selector, jobs)
    try:
        conn.sendall(_frame({"pid": pid}))
    except OSError:
        job.gone(selector, jobs)


def _refusal(request, fds, sources, startup) -> str | None:
    """Why the fork would not be the process the command would have started (None: it would be)."""
    if not isinstance(request, dict) or not _REQUEST <= request.keys() or len(fds) != len(_STREAMS):
        return "not a request with its three standard streams"
    if request["executable"] != sys.executable or request["path"] != sys.path:
        return f"another interpreter or sys.path ({request['executable']})"
    from voxpose.cli.main import thread_defaults

    theirs = _startup(thread_defaults(request["argv"]) | request["env"])  # as the command's ``main`` would set them
    for name in sorted(set(theirs) | set(startup)):
        if theirs.get(name) != startup.get(name):
            return f"{name} is {theirs.get(name)!r} for the command, {startup.get(name)!r} here"
    if _sources_changed(sources):
        return "a voxpose source file changed since the server started"
    return None


def _startup(env: dict) -> dict:
    return {name: value for name, value in env.items() if name.startswith(STARTUP_VARIABLES)}


def _sources_changed(sources: dict) -> bool:
    """Whether a file in ``sources`` (file -> time) changed; files of modules imported since are added."""
    now = _source_times()
    changed = any(now.get(file) != seen for file, seen in sources.items())
    for file, seen in now.items():
        sources.setdefault(file, seen)
    return changed


def _source_times() -> dict:
    """Modification time of every imported voxpose module's file (None: gone)."""
    times = {}
    for name, module in list(sys.modules.items()):
        file = getattr(module, "__file__", None)
        if file and (name == "voxpose" or name.startswith("voxpose.")):
            try:
                times[file] = os.stat(file).st_mtime_ns
            except OSError:
                times[file] = None
    return times


def _close_inherited(listener, selector, jobs, conn) -> None:
    """In a new fork: close the server's sockets and descriptors (a fork holding the listening socket would let
    commands connect after the server is gone, and wait for ever)."""
    for job in jobs.values():
        os.close(job.pidfd)
        if job.conn is not None:
            job.conn.close()
    selector.close()
    listener.close()
    conn.close()


def _child(request: dict, fds: list, runner) -> None:
    """In the fork: become the command's process, run it, exit with its status (never returns)."""
    status = 1
    try:
        signal.pthread_sigmask(signal.SIG_SETMASK, set())  # the server blocks SIGTERM outside its waits
        for sig in FORWARDED:  # as the command's own process would have them (a background job ignores SIGINT)
            default = signal.default_int_handler if sig == signal.SIGINT else signal.SIG_DFL
            signal.signal(sig, signal.SIG_IGN if sig in request["ignored"] else default)
        for target, fd in zip(_STREAMS, fds, strict=True):
            os.dup2(fd, target)
            os.close(fd)
        os.chdir(request["cwd"])
        os.environ.clear()
        os.environ.update(request["env"])
        sys.argv = ["voxpose", *request["argv"]]
        status = runner(request["argv"])
    except SystemExit as done:
        status = done.code if isinstance(done.code, int) else (0 if done.code is None else 1)
        if isinstance(done.code, str):
            sys.stderr.write(f"{done.code}\n")
    except BaseException:
        import traceback

        traceback.print_exc()
        status = 1
    finally:
        try:
            logging.shutdown()
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(status)


def preload() -> None:
    """Import every voxpose module, and numba's runtime with it, as a fork's first command would."""
    import importlib
    import pkgutil

    import voxpose

    for info in pkgutil.walk_packages(voxpose.__path__, "voxpose."):
        if info.name != "voxpose.__main__":  # `python -m voxpose` itself: importing it runs a command
            importlib.import_module(info.name)
    from voxpose import kernels

    if kernels.use_numba():
        kernels.load_runtime()


# -- the workflow's side --------------------------------------------------------------------------------------

# the thread variables Snakemake sets for every job to its `threads` (snakemake.shell): the server starts as a
# one-thread job would, so that its forks match the rules' jobs (all of them ask for 1 thread)
SNAKEMAKE_THREAD_VARIABLES = ("OMP_NUM_THREADS", "GOTO_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                              "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")  # fmt: skip


def start(log_file: str):
    """Start ``voxpose serve`` (the one on PATH, which the rules run) for this process's jobs, and name it in
    ``VOXPOSE_SERVER`` for them; a handle for ``stop``, or None where there is no server to start."""
    import shutil
    import subprocess
    import tempfile

    executable = shutil.which("voxpose")
    if executable is None or not hasattr(os, "pidfd_open"):
        return None
    folder = tempfile.mkdtemp(prefix="voxpose-server-")
    path = os.path.join(folder, "socket")
    env = os.environ | {name: "1" for name in SNAKEMAKE_THREAD_VARIABLES}
    os.makedirs(os.path.dirname(log_file) or ".", exist_ok=True)
    process = subprocess.Popen(
        [executable, "serve", "--socket", path, "--log", log_file],
        env=env,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,  # a Ctrl-C reaches the commands, which pass it on to their forks
    )
    os.environ[ENV] = path
    return process, folder


def stop(handle) -> None:
    """Stop a server from ``start`` (its forks still running are terminated) and forget it."""
    import shutil
    import subprocess

    process, folder = handle
    if os.environ.get(ENV, "").startswith(folder):
        del os.environ[ENV]
    process.terminate()
    try:
        process.wait(timeout=30)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
    shutil.rmtree(folder, ignore_errors=True)
