"""The quick configuration on a real single-node SLURM cluster on 127.0.0.1, checked against a local run (issue 9).

Run as root on Debian/Ubuntu, with ``voxpose[slurm]`` installed in the active environment:

    python tests/cluster/local_slurm.py [TARGET ...]     (or: VOXPOSE_SLURM_TEST=1 pytest tests/cluster -s)

(TARGETs: files to make instead of the whole quick DAG, e.g. one feature model, for a shorter check; their HDF5
content checksums are compared instead of the tables.)

1. Installs Debian's ``slurm-wlm`` and ``munge`` with apt-get if ``slurmctld`` is missing.
2. Starts munged, slurmctld and slurmd in the foreground as child processes, with their own key, socket and
   state in a temporary directory and a minimal /etc/slurm/slurm.conf (refused if one exists; removed at the end):
   one node and partition on 127.0.0.1, no accounting database, ``MinJobAge`` long enough for ``squeue`` status
   and ``scontrol show job`` afterwards.
3. Runs the quick configuration in two copies of the repository: locally (``--cores 2``) and through
   ``--workflow-profile profiles/slurm`` as shipped (its status command is not overridden; only the first status
   check comes sooner) on this cluster without accounting, where ``sacct`` is installed and fails, as it does on
   such sites. A run that stops making progress for ``STALL_S`` seconds is stopped and fails (the plugin polling a
   failing ``sacct`` forever was issue 21's hang). An ``sbatch`` wrapper first on PATH records every submission's
   arguments and job id.
4. Checks that every non-local Snakemake job ran inside a SLURM job, that each SLURM job COMPLETED with exit code 0
   and with the memory, time limit and CPUs that were requested (``scontrol show job``), that single jobs
   requested their rule's own resources and group jobs at least their members' largest, and that the tables are
   byte-identical to the local run's.
5. Stops the daemons by their process ids, whatever happened.
"""

import json
import os
import re
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# The default path, not SLURM_CONF: the plugin's job step drops SLURM_* variables before its nested srun.
SYSTEM_CONF = Path("/etc/slurm/slurm.conf")
MARK = "# written by voxpose tests/cluster/local_slurm.py; removed when it stops\n"
COPIED = ("Snakefile", "workflow", "config", "profiles")
CONFIG = "config/quick.yaml"
STALL_S = 600  # no new line in a run's log for this long: it hangs (a quick-config job takes well under a minute)

SLURM_CONF = """\
ClusterName=voxposetest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort={ctld_port}
SlurmdPort={slurmd_port}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket={d}/munge.socket
StateSaveLocation={d}/state
SlurmdSpoolDir={d}/spool
SlurmctldPidFile={d}/slurmctld.pid
SlurmdPidFile={d}/slurmd.pid
SlurmctldLogFile={d}/slurmctld.log
SlurmdLogFile={d}/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MinJobAge=3600
ReturnToService=2
NodeName=localhost NodeAddr=127.0.0.1 CPUs={cpus} RealMemory={mem_mb} State=UNKNOWN
PartitionName=main Nodes=localhost Default=YES MaxTime=INFINITE State=UP
"""

# Records each sbatch call (arguments and the job id it printed) as one JSON line, then passes the output on.
SBATCH_WRAPPER = """#!{python}
import json, subprocess, sys
proc = subprocess.run([{real!r}, *sys.argv[1:]], stdin=sys.stdin, capture_output=True, text=True)
sys.stdout.write(proc.stdout)
sys.stderr.write(proc.stderr)
with open({record!r}, "a") as f:
    f.write(json.dumps({{"args": sys.argv[1:], "out": proc.stdout.strip(), "rc": proc.returncode}}) + "\\n")
sys.exit(proc.returncode)
"""


def log(msg: str) -> None:
    print(f"[local_slurm {time.strftime('%H:%M:%S')}] {msg}", flush=True)


def ensure_packages() -> None:
    """Debian's slurm-wlm and munge (apt-get, as root) unless slurmctld, slurmd and munged are already there."""
    if all(shutil.which(t) for t in ("slurmctld", "slurmd", "munged", "sbatch", "squeue", "scontrol")):
        return
    log("installing slurm-wlm and munge with apt-get")
    env = os.environ | {"DEBIAN_FRONTEND": "noninteractive"}
    subprocess.run(["apt-get", "update", "-q"], check=True, env=env, stdout=subprocess.DEVNULL)
    cmd = ["apt-get", "install", "-y", "-q", "--no-install-recommends", "slurm-wlm", "munge"]
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class LocalSlurm:
    """munged + slurmctld + slurmd for one node on 127.0.0.1, as child processes stopped by PID on exit."""

    def __init__(self, directory: Path):
        self.dir = directory
        self.procs: list[subprocess.Popen] = []

    def _spawn(self, name: str, cmd: list[str]) -> None:
        out = open(self.dir / f"{name}.out", "w")
        self.procs.append(subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, ))
        log(f"started {name} pid {self.procs[-1].pid}")

    def __enter__(self):
        d = self.dir
        d.chmod(0o700)
        (d / "state").mkdir()
        (d / "spool").mkdir()
        key = d / "munge.key"
        key.write_bytes(os.urandom(1024))
        key.chmod(0o400)
        cpus = os.cpu_count() or 1
        mem_mb = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") // 2**20 - 512
        if SYSTEM_CONF.exists():
            raise RuntimeError(f"{SYSTEM_CONF} exists: this machine has a SLURM setup; not replacing it")
        conf = SLURM_CONF.format(d=d, ctld_port=free_port(), slurmd_port=free_port(), cpus=cpus, mem_mb=mem_mb)
        SYSTEM_CONF.parent.mkdir(parents=True, exist_ok=True)
        SYSTEM_CONF.write_text(MARK + conf)
        try:
            self._spawn("munged", ["munged", "-F", "--force", f"--key-file={key}", f"--socket={d}/munge.socket",
                                   f"--pid-file={d}/munged.pid", f"--log-file={d}/munged.log",
                                   f"--seed-file={d}/munged.seed"])
            self._wait(lambda: (d / "munge.socket").exists(), "munged socket")
            self._spawn("slurmctld", ["slurmctld", "-D"])
            self._spawn("slurmd", ["slurmd", "-D", "-N", "localhost"])
            self._wait(self._node_idle, "node idle in sinfo")
        except BaseException:
            self.__exit__()
            raise
        return self

    def _node_idle(self) -> bool:
        for p in self.procs:
            if p.poll() is not None:
                raise RuntimeError(f"daemon {p.args[0]} exited with {p.returncode}; see {self.dir}")
        out = subprocess.run(["sinfo", "-h", "-o", "%t"], capture_output=True, text=True).stdout
        return out.strip() == "idle"

    @staticmethod
    def _wait(ready, what: str, timeout: float = 60) -> None:
        end = time.monotonic() + timeout
        while not ready():
            if time.monotonic() > end:
                raise TimeoutError(f"timed out waiting for {what}")
            time.sleep(0.5)

    def __exit__(self, *exc):
        for p in reversed(self.procs):
            if p.poll() is None:
                os.kill(p.pid, signal.SIGTERM)
                try:
                    p.wait(timeout=30)
                except subprocess.TimeoutExpired:
                    os.kill(p.pid, signal.SIGKILL)
                    p.wait()
            log(f"stopped {Path(p.args[0]).name} pid {p.pid} (exit {p.returncode})")
        self.procs.clear()
        if SYSTEM_CONF.exists() and SYSTEM_CONF.read_text().startswith(MARK):
            SYSTEM_CONF.unlink()


def copy_repo(dest: Path) -> Path:
    dest.mkdir(parents=True)
    for item in COPIED:
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, dest / item)
    return dest


def snakemake(workdir: Path, args: list[str], env: dict, logfile: Path) -> float:
    """Run Snakemake to the end; fail if it does, or if its log stays silent for ``STALL_S`` seconds (a hang)."""
    cmd = [sys.executable, "-m", "snakemake", *args, "--configfile", CONFIG]
    log(f"({workdir.name}) {' '.join(cmd[1:])}")
    t0 = time.monotonic()
    with open(logfile, "w") as out:
        proc = subprocess.Popen(cmd, cwd=workdir, env=env, stdout=out, stderr=subprocess.STDOUT)
        while proc.poll() is None:
            time.sleep(5)
            if time.time() - logfile.stat().st_mtime > STALL_S:
                proc.send_signal(signal.SIGINT)  # Snakemake cancels its SLURM jobs on an interrupt
                try:
                    proc.wait(timeout=120)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    proc.wait()
                raise AssertionError(f"snakemake in {workdir} hung: no progress for {STALL_S} s; last lines of "
                                     f"{logfile}:\n{logfile.read_text()[-3000:]}")  # fmt: skip
    if proc.returncode != 0:
        raise AssertionError(f"snakemake failed in {workdir}; last lines of {logfile}:\n{logfile.read_text()[-5000:]}")
    return time.monotonic() - t0


def check_without_accounting() -> str:
    """This cluster is one the shipped profile must survive: sacct installed, and failing."""
    proc = subprocess.run(["sacct", "-n", "-X"], capture_output=True, text=True)
    assert proc.returncode != 0 or "disabled" in proc.stderr, f"sacct works here: {proc.stdout}{proc.stderr}"
    return f"sacct fails here, as on a cluster without accounting: {proc.stderr.strip().splitlines()[-1]}"


def job_key(rule: str, wildcards: dict) -> str:
    return rule + ":" + ",".join(f"{k}={v}" for k, v in sorted(wildcards.items()))


def logged_jobs(text: str) -> dict[str, dict]:
    """Jobs a Snakemake log announced (group members included): rule:wildcards -> {local, mem_mb, runtime}."""
    jobs = {}
    for m in re.finditer(r"^( *)(localrule|rule) (\w+):\n((?:\1 +\S.*\n)+)", text, re.M):
        body = m.group(4)
        wildcards = re.search(r"^ *wildcards: (.*)$", body, re.M)
        wildcards = dict(kv.split("=", 1) for kv in wildcards.group(1).split(", ")) if wildcards else {}
        resources = dict(re.findall(r"\b(mem_mb|runtime)=(\d+)", body))
        jobs[job_key(m.group(3), wildcards)] = {
            "local": m.group(2) == "localrule", **{k: int(v) for k, v in resources.items()}
        }
    return jobs


def sbatch_requests(record: Path) -> dict[str, dict]:
    """SLURM job id -> what sbatch was asked for (mem MB, minutes, cpus) and the Snakemake jobs it runs."""
    out = {}
    for line in record.read_text().splitlines():
        call = json.loads(line)
        assert call["rc"] == 0, f"sbatch failed: {call}"
        args = " ".join(call["args"])
        targets = re.search(r"--target-jobs (.*?) --", args).group(1)
        members = []
        for spec in shlex.split(targets):
            rule, _, wildcards = spec.partition(":")
            members.append(job_key(rule, dict(kv.split("=", 1) for kv in wildcards.split(",") if kv)))
        out[call["out"].split(";")[0]] = {
            "mem_mb": int(re.search(r"--mem (\d+)", args).group(1)),
            "runtime": int(re.search(r"-t '?(\d+)", args).group(1)),
            "cpus": int(re.search(r"--cpus-per-task=(\d+)", args).group(1)),
            "jobs": members,
        }
    return out


def scontrol_job(job_id: str) -> dict:
    out = subprocess.run(["scontrol", "-o", "show", "job", job_id], capture_output=True, text=True, check=True).stdout
    return dict(re.findall(r"(\w+)=(\S*)", out))


def minutes(limit: str) -> int:
    """SLURM's TimeLimit ([D-]HH:MM:SS) in minutes."""
    days, _, hms = limit.rpartition("-")
    h, m, s = map(int, hms.split(":"))
    return int(days or 0) * 1440 + h * 60 + m + (s > 0)


def mem_mb(value: str) -> int:
    units = {"M": 1, "G": 1024, "T": 1024**2}
    return int(float(value[:-1]) * units[value[-1]])


def check_cluster_run(text: str, record: Path) -> list[str]:
    """Every non-local job ran in a completed SLURM job with the resources it asked for; returns report lines."""
    jobs = logged_jobs(text)
    requests = sbatch_requests(record)
    ran = [j for req in requests.values() for j in req["jobs"]]
    assert len(ran) == len(set(ran)), "a Snakemake job was submitted twice"
    remote = {j for j, info in jobs.items() if not info["local"]}
    assert set(ran) == remote, f"submitted {sorted(set(ran) - remote)}; not submitted {sorted(remote - set(ran))}"
    lines = [f"{'slurm id':>8s} {'state':10s} {'mem MB req/got':>15s} {'time req/got':>14s} {'cpus':>4s}  jobs"]
    for sid, req in sorted(requests.items(), key=lambda kv: int(kv[0])):
        got = scontrol_job(sid)
        assert got["JobState"] == "COMPLETED" and got["ExitCode"] == "0:0", f"SLURM job {sid}: {got}"
        assert mem_mb(got["MinMemoryNode"]) == req["mem_mb"], f"SLURM job {sid} memory {got['MinMemoryNode']}"
        assert minutes(got["TimeLimit"]) == req["runtime"], f"SLURM job {sid} time limit {got['TimeLimit']}"
        assert int(got["NumCPUs"]) == req["cpus"], f"SLURM job {sid} cpus {got['NumCPUs']}"
        infos = [jobs[j] for j in req["jobs"]]
        if len(infos) == 1:  # a single job asks for exactly its rule's resources
            assert (req["mem_mb"], req["runtime"]) == (infos[0]["mem_mb"], infos[0]["runtime"]), (sid, req, infos)
        else:  # a group job asks for at least what its largest member needs
            assert req["mem_mb"] >= max(i["mem_mb"] for i in infos), (sid, req, infos)
            assert req["runtime"] >= max(i["runtime"] for i in infos), (sid, req, infos)
        rules = sorted({j.split(":")[0] for j in req["jobs"]})
        lines.append(
            f"{sid:>8s} {got['JobState']:10s} {req['mem_mb']:6d}/{got['MinMemoryNode']:>8s} "
            f"{req['runtime']:4d}m/{got['TimeLimit']:>8s} {got['NumCPUs']:>4s}  {len(infos)} x {','.join(rules)}"
        )
    n_local = sum(info["local"] for info in jobs.values())
    lines.append(f"{len(remote)} non-local Snakemake jobs ran in {len(requests)} SLURM jobs; {n_local} ran locally")
    return lines


def compare_checksums(local: Path, cluster: Path, targets: list[str]) -> list[str]:
    """The targets' HDF5 content checksums (voxpose.io.checksum) agree between the two runs."""
    import h5py

    lines = []
    for target in targets:
        sums = []
        for run in (local, cluster):
            with h5py.File(run / target, "r") as f:
                sums.append(f.attrs["checksum"])
        assert sums[0] == sums[1], f"{target} differs between the local and the SLURM run"
        lines.append(f"identical content: {target} ({sums[0]})")
    return lines


def compare_tables(local: Path, cluster: Path) -> list[str]:
    names = sorted(p.relative_to(local) for p in (local / "results/tables").glob("*.*"))
    assert names, "the local run wrote no tables"
    lines = []
    for name in names:
        a, b = (local / name).read_bytes(), (cluster / name).read_bytes()
        assert a == b, f"{name} differs between the local and the SLURM run"
        lines.append(f"identical: {name} ({len(a)} bytes)")
    return lines


def main(targets: list[str]) -> int:
    if os.geteuid() != 0:
        sys.exit("local_slurm: must run as root (installs packages, runs slurmd)")
    t_start = time.monotonic()
    ensure_packages()
    tmp = Path(tempfile.mkdtemp(prefix="voxpose-slurm-"))
    try:
        (tmp / "slurm").mkdir()
        bin_dir = tmp / "bin"
        bin_dir.mkdir()
        record = tmp / "sbatch.jsonl"
        record.touch()
        wrapper = bin_dir / "sbatch"
        wrapper.write_text(SBATCH_WRAPPER.format(python=sys.executable, real=shutil.which("sbatch"),
                                                 record=str(record)))
        wrapper.chmod(0o755)
        path = os.pathsep.join([str(bin_dir), str(Path(sys.executable).parent), os.environ["PATH"]])
        local, cluster = copy_repo(tmp / "local"), copy_repo(tmp / "cluster")
        with LocalSlurm(tmp / "slurm"):
            env = os.environ | {"PATH": path}
            report = [check_without_accounting()]
            t_cluster = snakemake(cluster, ["--workflow-profile", "profiles/slurm",
                                            "--slurm-init-seconds-before-status-checks", "5", *targets],
                                  env, tmp / "cluster.log")  # fmt: skip
            log(f"SLURM run took {t_cluster:.0f} s")
            report += check_cluster_run((tmp / "cluster.log").read_text(), record)
        t_local = snakemake(local, ["--cores", "2", *targets], os.environ | {"PATH": path}, tmp / "local.log")
        log(f"local run took {t_local:.0f} s")
        report += compare_checksums(local, cluster, targets) if targets else compare_tables(local, cluster)
    except BaseException:
        log(f"FAILED; kept {tmp} (logs: cluster.log, local.log, slurm/, cluster/.snakemake/slurm_logs)")
        raise
    shutil.rmtree(tmp)
    print("\n".join(report))
    log(f"PASSED in {time.monotonic() - t_start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
