"""The job server (``voxpose.cli.job_server``): a served command behaves as the command run alone (output, streams,
exit status, errors); the server refuses what its fork would run differently, and commands then run alone; signals
reach the fork; the server goes when stopped or orphaned. The workflow's run through it is checked against the
reference tables in ``tests/workflow``."""

import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from voxpose.cli import job_server

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.skipif(not hasattr(os, "pidfd_open"), reason="the job server needs Linux (os.pidfd_open)")

# A server whose runner is a stand-in command, for the process mechanics: `sleep S`, `exit N`, `echo WORDS`
_STAND_IN = """\
import logging, sys, time
from voxpose.cli import job_server

logging.basicConfig(level=logging.INFO)

def runner(argv):
    if argv[0] == "sleep":
        time.sleep(float(argv[1]))
    elif argv[0] == "exit":
        return int(argv[1])
    elif argv[0] == "echo":
        print(" ".join(argv[1:]))
    return 0

job_server.serve(sys.argv[1], runner)
"""
# The command's side, run from the same folder as the stand-in (same sys.path); 99: it would have run alone
_CLIENT = """\
import sys
from voxpose.cli import job_server

status = job_server.run_remote(sys.argv[1:])
sys.exit(99 if status is None else status)
"""


def _wait_for(predicate, seconds=60.0):
    end = time.monotonic() + seconds
    while not predicate():
        assert time.monotonic() < end, "timed out"
        time.sleep(0.02)


def _env(**extra):
    """This environment as a one-thread Snakemake job's (the thread variables at 1), ``extra`` added."""
    env = {k: v for k, v in os.environ.items() if k != job_server.ENV}
    return env | dict.fromkeys(job_server.SNAKEMAKE_THREAD_VARIABLES, "1") | {"PYTHONPATH": str(ROOT)} | extra


@pytest.fixture()
def stand_in(tmp_path):
    """A stand-in server on a socket in ``tmp_path``: (socket path, its Popen, its stderr log path)."""
    script = tmp_path / "serve.py"
    script.write_text(_STAND_IN)
    (tmp_path / "client.py").write_text(_CLIENT)
    sock, log = tmp_path / "s.sock", tmp_path / "server.log"
    with open(log, "w") as err:
        proc = subprocess.Popen([sys.executable, str(script), str(sock)], cwd=tmp_path, env=_env(), stderr=err)
    _wait_for(sock.exists)
    yield sock, proc, log
    proc.terminate()
    proc.wait(timeout=30)


def _client(sock, *argv, sigint=signal.SIG_DFL, **popen):
    """The command's side with ``argv``, SIGINT handled as ``sigint`` (a job run in the background ignores it)."""
    client = sock.parent / "client.py"
    return subprocess.Popen([sys.executable, str(client), *argv], env=_env(VOXPOSE_SERVER=str(sock)),
                            preexec_fn=lambda: signal.signal(signal.SIGINT, sigint), **popen)  # fmt: skip


def _ignores(pid: int, sig) -> bool:
    """Whether process ``pid`` ignores ``sig`` (its SigIgn mask in /proc)."""
    mask = next(line for line in Path(f"/proc/{pid}/status").read_text().splitlines() if line.startswith("SigIgn"))
    return bool(int(mask.split()[1], 16) >> (sig - 1) & 1)


def test_the_fork_writes_to_the_commands_streams_and_its_status_is_the_commands(stand_in, tmp_path):
    sock, _, _ = stand_in
    out = subprocess.run([sys.executable, str(tmp_path / "client.py"), "echo", "hello", "there"],
                         env=_env(VOXPOSE_SERVER=str(sock)), capture_output=True, text=True)  # fmt: skip
    assert (out.returncode, out.stdout) == (0, "hello there\n")
    assert _client(sock, "exit", "3").wait(timeout=30) == 3


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_to_the_command_reaches_its_fork(stand_in, sig):
    sock, _, _ = stand_in
    client = _client(sock, "sleep", "60")
    _wait_for(lambda: _forks(stand_in[1].pid))
    fork = _forks(stand_in[1].pid)[0]
    client.send_signal(sig)
    # SIGTERM kills the fork (128 + 15); SIGINT raises KeyboardInterrupt in it, a traceback and status 1
    assert client.wait(timeout=30) == (143 if sig == signal.SIGTERM else 1)
    _wait_for(lambda: not Path(f"/proc/{fork}").exists())


@pytest.mark.parametrize("sigint", [signal.SIG_DFL, signal.SIG_IGN])
def test_the_fork_ignores_sigint_as_the_command_does(stand_in, sigint):
    sock, server, _ = stand_in
    client = _client(sock, "sleep", "60", sigint=sigint)
    _wait_for(lambda: _forks(server.pid))
    fork = _forks(server.pid)[0]
    assert _ignores(fork, signal.SIGINT) == (sigint == signal.SIG_IGN)
    assert not _ignores(fork, signal.SIGTERM)
    client.terminate()
    assert client.wait(timeout=30) == 143


def test_a_command_killed_outright_takes_its_fork_with_it(stand_in):
    sock, server, log = stand_in
    client = _client(sock, "sleep", "60")
    _wait_for(lambda: _forks(server.pid))
    fork = _forks(server.pid)[0]
    client.kill()
    client.wait()
    _wait_for(lambda: not _forks(server.pid))
    assert "its command went away" in log.read_text()
    assert f"job {fork}: exit 143" in log.read_text()


def test_stopping_the_server_stops_its_forks_and_removes_its_socket(stand_in):
    sock, server, _ = stand_in
    client = _client(sock, "sleep", "60", stderr=subprocess.PIPE)
    _wait_for(lambda: _forks(server.pid))
    server.terminate()
    assert server.wait(timeout=30) == 0
    assert client.wait(timeout=30) == 1  # the command says the server stopped before it ended
    assert b"stopped before the command ended" in client.stderr.read()
    assert not sock.exists()


@pytest.mark.parametrize("garbage", [b"", b"\x00\x00\x00\x05{}{}{", b"\x00\x00\x00\x02{}"])
def test_a_broken_request_is_refused_and_the_server_goes_on(stand_in, garbage):
    sock, _, log = stand_in
    with socket.socket(socket.AF_UNIX) as conn:  # no streams passed, and no (or a broken, or an empty) request
        conn.connect(str(sock))
        conn.sendall(garbage)
        conn.shutdown(socket.SHUT_WR)
        assert conn.recv(100) == b""  # closed without a pid
    _wait_for(lambda: "refused" in log.read_text())
    assert _client(sock, "exit", "4").wait(timeout=30) == 4


def test_the_server_leaves_when_the_process_that_started_it_is_gone(tmp_path):
    (tmp_path / "serve.py").write_text(_STAND_IN)
    sock = tmp_path / "s.sock"
    parent = subprocess.Popen(["sh", "-c", f"{sys.executable} serve.py s.sock & sleep 1"], cwd=tmp_path, env=_env())
    _wait_for(sock.exists)
    parent.wait(timeout=30)
    _wait_for(lambda: not sock.exists(), seconds=30)  # checked every second


def _forks(server_pid: int) -> list:
    """The server's child processes."""
    children = Path(f"/proc/{server_pid}/task/{server_pid}/children")
    return [int(p) for p in children.read_text().split()] if children.exists() else []


# -- the real server and the real command ---------------------------------------------------------------------


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """``python -m voxpose serve`` (the clients below run ``python -m voxpose`` from the same folder, so that the
    interpreter and sys.path match): (socket path, log path)."""
    folder = tmp_path_factory.mktemp("server")
    sock, log = folder / "s.sock", folder / "server.log"
    proc = subprocess.Popen([sys.executable, "-m", "voxpose", "serve", "--socket", str(sock), "--log", str(log)],
                            cwd=folder, env=_env(), stderr=subprocess.DEVNULL)  # fmt: skip
    _wait_for(sock.exists)
    yield sock, log
    proc.terminate()
    proc.wait(timeout=30)


def _voxpose(folder, *argv, server=None, **env):
    extra = {job_server.ENV: str(server)} if server else {}
    return subprocess.run([sys.executable, "-m", "voxpose", *argv], cwd=folder, env=_env(**extra, **env),
                          capture_output=True, text=True)  # fmt: skip


def test_a_served_command_writes_what_it_writes_alone(server):
    sock, log = server
    folder = sock.parent
    args = ["generate", "--kind", "jog", "--index", "1", "--frames", "30", "--seed", "4"]
    served = _voxpose(folder, *args, "-o", "served.bvh", server=sock)
    alone = _voxpose(folder, *args, "-o", "alone.bvh")
    assert served.returncode == alone.returncode == 0, served.stderr
    assert (folder / "served.bvh").read_bytes() == (folder / "alone.bvh").read_bytes()
    assert any("exit 0" in line and "served.bvh" in line for line in log.read_text().splitlines())


@pytest.mark.parametrize(
    "argv",
    [
        ["generate", "--kind", "jog", "--index", "0", "--frames", "30", "--seed", "4", "-o", "."],  # a folder
        ["generate", "--kind", "crawl"],  # the parser's error
        ["check-config", "--base", "absent.yaml"],
    ],
)
def test_a_served_mistake_is_the_same_one_line_error_and_status(server, argv):
    sock, log = server
    served, alone = _voxpose(sock.parent, *argv, server=sock), _voxpose(sock.parent, *argv)
    served_line = ": voxpose " + " ".join(argv)  # the server's line for this job: it was served, not run alone
    assert any(" exit 2 after " in line and line.endswith(served_line) for line in log.read_text().splitlines())
    assert served.returncode == alone.returncode == 2
    assert served.stderr.splitlines()[-1] == alone.stderr.splitlines()[-1]
    assert served.stderr.splitlines()[-1].startswith("voxpose: error: ")


def test_a_command_whose_startup_variables_differ_runs_alone(server):
    sock, log = server
    out = _voxpose(sock.parent, "check-config", "--base", str(ROOT / "config" / "config.yaml"), server=sock,
                   NUMBA_OPT="1")  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert "refused: NUMBA_OPT is '1' for the command, None here" in log.read_text()


def test_a_command_with_no_server_answering_runs_alone(tmp_path):
    out = _voxpose(tmp_path, "check-config", "--base", str(ROOT / "config" / "config.yaml"),
                   server=tmp_path / "nobody.sock")  # fmt: skip
    assert out.returncode == 0, out.stderr


def test_an_edited_source_file_is_refused(tmp_path):
    """A server keeps the code it imported: after an edit of voxpose, commands run alone (on the new code)."""
    package = tmp_path / "voxpose"
    subprocess.run(["cp", "-r", str(ROOT / "voxpose"), str(package)], check=True)
    sock, log = tmp_path / "s.sock", tmp_path / "server.log"
    env = _env(PYTHONPATH=str(tmp_path))
    proc = subprocess.Popen([sys.executable, "-m", "voxpose", "serve", "--socket", str(sock), "--log", str(log)],
                            cwd=tmp_path, env=env, stderr=subprocess.DEVNULL)  # fmt: skip
    try:
        _wait_for(sock.exists)
        argv = [sys.executable, "-m", "voxpose", "check-config", "--base", str(ROOT / "config" / "config.yaml")]
        run = {"cwd": tmp_path, "env": env | {job_server.ENV: str(sock)}, "capture_output": True}
        assert subprocess.run(argv, **run).returncode == 0
        assert "exit 0" in log.read_text()
        os.utime(package / "errors.py", ns=(time.time_ns(), time.time_ns() + 10**9))
        assert subprocess.run(argv, **run).returncode == 0
        assert "refused: a voxpose source file changed since the server started" in log.read_text()
    finally:
        proc.terminate()
        proc.wait(timeout=30)


def test_preload_imports_every_module_and_numba_but_runs_no_command():
    """``voxpose.__main__`` runs the command in ``sys.argv`` when imported: preload leaves it out."""
    code = (
        "import pkgutil, sys\n"
        "sys.argv = ['voxpose', 'check-config', '--base', 'absent.yaml']\n"
        "import voxpose\n"
        "from voxpose.cli import job_server\n"
        "job_server.preload()\n"
        "names = [i.name for i in pkgutil.walk_packages(voxpose.__path__, 'voxpose.')]\n"
        "print(sorted(set(names) - set(sys.modules)), 'numba' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=_env(), capture_output=True, text=True)
    assert (out.returncode, out.stdout) == (0, "['voxpose.__main__'] True\n"), out.stderr


def test_start_names_the_server_for_jobs_and_stop_removes_it(tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    monkeypatch.delenv(job_server.ENV, raising=False)
    handle = job_server.start(str(tmp_path / "logs" / "server.log"))
    assert handle is not None
    sock = Path(os.environ[job_server.ENV])
    try:
        _wait_for(sock.exists)
        for name in job_server.SNAKEMAKE_THREAD_VARIABLES:  # the server starts as a one-thread job would
            assert Path(f"/proc/{handle[0].pid}/environ").read_bytes().count(f"{name}=1\0".encode()) == 1
    finally:
        job_server.stop(handle)
    assert job_server.ENV not in os.environ
    assert not sock.parent.exists()
    assert handle[0].returncode == 0
