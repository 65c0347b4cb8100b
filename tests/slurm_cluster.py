"""A single-node SLURM cluster on this host, for the tests and CI (and for trying the slurm profile).

If a SLURM cluster already answers on this host (through ``SLURM_CONF``, ``/etc/slurm/slurm.conf``
or a configless slurmd's ``/run/slurm/conf``) and has a node that takes jobs, it is used as it is.
Otherwise :func:`start_cluster` starts one from Debian's packages (``apt-get install slurm-wlm
munge``), as root, with its configuration, state and logs in one folder:

- ``munged`` with a fresh key (1 KiB random, mode 0400) on munge's default socket
  ``/run/munge/munge.socket.2``, unless a munged already answers there (then that one is used);
- ``slurm.conf`` for this host: the node's CPUs, sockets, cores and memory as ``slurmd -C``
  reports them (less 512 MB for the system), one partition ``gridlib`` (the default), the two
  daemons on free ports of the loopback address, ``SlurmUser=root``;
- no slurmdbd: ``AccountingStorageType=accounting_storage/none`` (``sacct`` answers "accounting
  storage is disabled"), but every finished job is appended to ``logs/jobcomp.log``
  (``jobcomp/filetxt``: JobId, JobState, Name, NodeList...), and ``MinJobAge=3600`` keeps
  finished jobs in ``squeue`` and ``scontrol`` for an hour;
- no cgroups: ``ProctrackType=proctrack/linuxproc``, ``TaskPlugin=task/none`` and
  ``JobAcctGatherType=jobacct_gather/none``: linuxproc tracks a job's processes by their parent
  chain and works on any Linux. The cgroup plugins depend on how the machine mounts cgroups:
  on the project's VMs (no systemd; the cgroup v1 controllers mounted under /sys/fs/cgroup)
  ``proctrack/cgroup`` and ``task/cgroup`` work too and enforce memory limits, but under the
  unified v2 hierarchy Slurm 22.05 wants systemd to delegate a subtree to slurmd. Without
  them a job's memory and CPUs are not enforced: fine for these tests, not for production;
- ``slurmctld -D`` with that file and ``slurmd -D`` *configless* (``--conf-server``): slurmd
  fetches the configuration from slurmctld and links its copy at ``/run/slurm/conf``, where SLURM
  commands look when neither ``SLURM_CONF`` nor ``/etc/slurm/slurm.conf`` is there. This is what
  makes jobs work: snakemake-executor-plugin-slurm's job step runs ``srun`` with every ``SLURM_*``
  variable removed, ``SLURM_CONF`` included, so ``srun`` inside a job must find the configuration
  in a standard place. (The reason munged uses its default socket: configless slurmd asks munge
  before it has a configuration that could name another socket.)

One such cluster per host: ``/run/slurm/conf`` and munge's socket are the host's (a second test
session finds the first one's cluster running and uses it). Start-up takes about a second on
the project's VM. Every failure raises :class:`ClusterError`
with one message saying what failed and which log to read. :meth:`SlurmCluster.stop` cancels
the cluster's jobs, ends the daemons that were started and removes ``/run/slurm/conf``.

Used by the session fixture ``slurm_cluster`` (tests/workflow/conftest.py); by hand, as root::

    python tests/slurm_cluster.py start /tmp/gridlib-slurm   # prints: export SLURM_CONF=...
    python tests/slurm_cluster.py stop /tmp/gridlib-slurm
"""

from __future__ import annotations

import contextlib
import getpass
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

DAEMONS = ("munged", "slurmctld", "slurmd")
CLIENTS = ("munge", "unmunge", "sinfo", "squeue", "sbatch", "scontrol", "scancel", "srun")
PARTITION = "gridlib"
MUNGE_SOCKET = Path("/run/munge/munge.socket.2")  # libmunge's default
SYSTEM_CONF = Path("/etc/slurm/slurm.conf")  # SLURM's default configuration file
CONF_LINK = Path("/run/slurm/conf")  # a configless slurmd's copy, read when neither of those exists
# Node states in which a node takes jobs (sinfo %T, lower case, flags such as * stripped).
READY_STATES = {"idle", "mixed", "allocated", "completing"}
CLIENT_TIMEOUT = 20  # seconds for one SLURM or munge command


class ClusterError(RuntimeError):
    """The cluster could not be started or used; the message says what failed and which log to read."""


class SlurmUnavailable(ClusterError):
    """No cluster answers and none can be started here: SLURM's or munge's programs are not on
    PATH (Debian: apt-get install slurm-wlm munge), or this is not root."""


@dataclass
class SlurmCluster:
    """A SLURM cluster that answers on this host.

    ``env`` is the environment for SLURM commands and for Snakemake (with ``SLURM_CONF`` for a
    started cluster); ``folder`` holds a started cluster's configuration, state and logs (None
    for a cluster that was running already, which :meth:`stop` leaves alone).
    """

    env: dict[str, str]
    partition: str
    nodes: list[str]
    folder: Path | None = None
    start_seconds: float = 0.0
    processes: dict[str, subprocess.Popen] = field(default_factory=dict, repr=False)

    @property
    def started(self) -> bool:
        return self.folder is not None

    def log(self, name: str) -> Path:
        """A started cluster's log: ``munged``, ``slurmctld``, ``slurmd`` or ``jobcomp``."""
        if self.folder is None:
            raise ClusterError("this SLURM cluster was not started here: its logs are its administrator's")
        return self.folder / "logs" / f"{name}.log"

    def run(self, *args: str, check: bool = True) -> subprocess.CompletedProcess:
        """A SLURM command against this cluster (``squeue``, ``scontrol``...)."""
        return _command(list(args), self.env, check=check)

    def job_states(self, job_ids: list[str]) -> dict[str, str]:
        """The state (COMPLETED, FAILED, RUNNING...) of each of ``job_ids`` that SLURM knows.

        A started cluster answers from its job completion log (every job that ended, however
        long ago), then ``scontrol`` for the others; a cluster that was running already answers
        from ``scontrol``, which forgets a finished job after the cluster's MinJobAge.
        """
        states: dict[str, str] = {}
        if self.folder is not None and self.log("jobcomp").exists():
            for line in self.log("jobcomp").read_text().splitlines():
                record = dict(re.findall(r"(\w+)=(\S*)", line))
                if "JobId" in record:
                    states[record["JobId"]] = record.get("JobState", "")
        for job in job_ids:
            if job not in states:
                res = self.run("scontrol", "--oneliner", "show", "job", job, check=False)
                found = re.search(r"\bJobState=(\S+)", res.stdout)
                if res.returncode == 0 and found:
                    states[job] = found.group(1)
        return {job: states[job] for job in job_ids if job in states}

    def stop(self) -> None:
        """Cancel a started cluster's jobs, end the daemons started here, remove /run/slurm/conf."""
        if self.folder is None:
            return
        ctld = self.processes.get("slurmctld")
        if ctld is not None and ctld.poll() is None:
            self.run("scancel", "--user", getpass.getuser(), check=False)
        for name in reversed(DAEMONS):  # slurmd, slurmctld, then munged
            _end(self.processes.pop(name, None))
        _remove_conf_link(self.folder)


def _command(
    args: list[str], env: dict[str, str] | None = None, check: bool = True, stdin: str | None = None
) -> subprocess.CompletedProcess:
    try:
        res = subprocess.run(
            args, env=env, input=stdin, capture_output=True, text=True, timeout=CLIENT_TIMEOUT
        )
    except subprocess.TimeoutExpired as exc:
        raise ClusterError(f"SLURM: `{' '.join(args)}` did not answer in {CLIENT_TIMEOUT} s") from exc
    if check and res.returncode != 0:
        raise ClusterError(f"SLURM: `{' '.join(args)}` failed: {(res.stderr or res.stdout).strip()}")
    return res


def _end(process: subprocess.Popen | None, wait: float = 10.0) -> None:
    if process is None or process.poll() is not None:
        return
    process.send_signal(signal.SIGTERM)
    try:
        process.wait(wait)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait(wait)


def _remove_conf_link(folder: Path) -> None:
    """Remove /run/slurm/conf if it is the link of this folder's slurmd."""
    if CONF_LINK.is_symlink() and Path(os.readlink(CONF_LINK)).is_relative_to(folder):
        CONF_LINK.unlink()


def missing_programs() -> list[str]:
    """The SLURM and munge programs this module needs that are not on PATH."""
    return [p for p in (*DAEMONS, *CLIENTS) if shutil.which(p) is None]


def node_states(env: dict[str, str]) -> dict[str, str] | None:
    """Node name -> state (idle, down...) of the cluster ``env`` points to; None if none answers."""
    try:
        res = _command(["sinfo", "--noheader", "--Node", "--format=%N %T"], env, check=False)
    except (OSError, ClusterError):
        return None
    if res.returncode != 0:
        return None
    states = {}
    for line in res.stdout.splitlines():
        name, _, state = line.strip().partition(" ")
        if name:
            states[name] = state.strip().rstrip("*~#!%$@^-").lower()
    return states


def default_partition(env: dict[str, str]) -> str:
    names = _command(["sinfo", "--noheader", "--format=%P"], env).stdout.split()
    marked = [p.rstrip("*") for p in names if p.endswith("*")]
    return marked[0] if marked else (names[0] if names else "")


def running_cluster(env: dict[str, str] | None = None) -> SlurmCluster | None:
    """The cluster already configured on this host if it has a node that takes jobs, else None.

    Only a configured one is asked (``SLURM_CONF``, ``/etc/slurm/slurm.conf`` or
    ``/run/slurm/conf``): without one, SLURM's commands look for a configuration server in DNS.
    """
    env = dict(os.environ if env is None else env)
    if shutil.which("sinfo") is None:
        return None
    if not (env.get("SLURM_CONF") or SYSTEM_CONF.exists() or (CONF_LINK / "slurm.conf").exists()):
        return None
    ready = sorted(n for n, s in (node_states(env) or {}).items() if s in READY_STATES)
    if not ready:
        return None
    return SlurmCluster(env=env, partition=default_partition(env), nodes=ready)


def munge_answers() -> bool:
    """Whether a munged on the default socket encodes and decodes a credential."""
    cred = _command(["munge", "--no-input"], check=False)
    return cred.returncode == 0 and _command(["unmunge"], check=False, stdin=cred.stdout).returncode == 0


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def node_line(name: str) -> str:
    """This machine's node definition from ``slurmd -C`` (CPUs, topology, memory)."""
    res = _command(["slurmd", "-C"], check=False)
    first = res.stdout.splitlines()[0] if res.returncode == 0 and res.stdout else ""
    if not first.startswith("NodeName="):
        raise ClusterError(f"SLURM: `slurmd -C` did not describe this machine: {res.stderr.strip()}")
    fields = dict(item.split("=", 1) for item in first.split())
    del fields["NodeName"]
    fields.pop("UpTime", None)
    # Leave the system some memory: a node whose RealMemory exceeds what slurmd finds is drained.
    fields["RealMemory"] = str(max(int(fields.get("RealMemory", "1024")) - 512, 256))
    return f"NodeName={name} NodeAddr=127.0.0.1 {' '.join(f'{k}={v}' for k, v in fields.items())}"


def write_config(folder: Path, node: str) -> Path:
    """slurm.conf of a single-node cluster in ``folder`` (and the folders it names)."""
    logs, state = folder / "logs", folder / "state"
    for sub in (logs, state / "slurmctld", state / "slurmd"):
        sub.mkdir(parents=True, exist_ok=True)
    conf = folder / "slurm.conf"
    conf.write_text(
        f"""\
# A single-node SLURM cluster for gridlib's tests (tests/slurm_cluster.py); not for production.
ClusterName=gridlib
SlurmctldHost={node}(127.0.0.1)
SlurmctldPort={_free_port()}
SlurmdPort={_free_port()}
SlurmctldParameters=enable_configless
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
StateSaveLocation={state / "slurmctld"}
SlurmdSpoolDir={state / "slurmd"}
SlurmctldPidFile={state / "slurmctld.pid"}
SlurmdPidFile={state / "slurmd.pid"}
SlurmctldLogFile={logs / "slurmctld.log"}
SlurmdLogFile={logs / "slurmd.log"}
SlurmctldDebug=info
SlurmdDebug=info
# No cgroups (they depend on the machine's cgroup mounts): processes tracked by their
# parents, memory and CPU limits not enforced.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
# No slurmdbd, so no accounting (sacct fails); ended jobs are appended to jobcomp.log and
# stay in squeue for an hour.
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc={logs / "jobcomp.log"}
MinJobAge=3600
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
KillWait=5
{node_line(node)} State=UNKNOWN
PartitionName={PARTITION} Nodes={node} Default=YES MaxTime=INFINITE State=UP
"""
    )
    return conf


def _port(conf: Path, key: str) -> str:
    found = re.search(rf"^{key}=(\d+)$", conf.read_text(), re.MULTILINE)
    assert found, key
    return found.group(1)


def _tail(path: Path, lines: int = 8) -> str:
    text = path.read_text(errors="replace").strip() if path.exists() else ""
    return "\n    ".join(text.splitlines()[-lines:]) if text else "(empty)"


def start_cluster(folder: Path, timeout: float = 60.0) -> SlurmCluster:
    """Start munged (if none answers), slurmctld and slurmd for this host with configuration,
    state and logs in ``folder``; wait at most ``timeout`` seconds until the node is idle."""
    missing = missing_programs()
    if missing:
        raise SlurmUnavailable(
            f"SLURM: {', '.join(missing)} not found on PATH (Debian: apt-get install slurm-wlm munge)"
        )
    if os.geteuid() != 0:
        raise SlurmUnavailable("SLURM: starting a test cluster needs root (slurmd runs jobs as their users)")
    if SYSTEM_CONF.exists():
        raise ClusterError(
            f"SLURM test cluster: {SYSTEM_CONF} exists but its cluster does not answer (sinfo); commands "
            "inside jobs would read it (the executor plugin's job step drops SLURM_CONF): start that "
            "cluster, or move the file away to let the tests start their own"
        )
    t0 = time.perf_counter()
    folder = Path(folder).resolve()
    node = socket.gethostname().split(".")[0]
    conf = write_config(folder, node)
    logs = folder / "logs"
    env = {**os.environ, "SLURM_CONF": str(conf)}
    cluster = SlurmCluster(env=env, partition=PARTITION, nodes=[node], folder=folder)
    commands: dict[str, list[str]] = {
        "slurmctld": ["slurmctld", "-D", "-i", "-f", str(conf)],
        "slurmd": ["slurmd", "-D", "--conf-server", f"127.0.0.1:{_port(conf, 'SlurmctldPort')}", "-N", node],
    }
    ready: dict[str, Callable[[], bool]] = {
        "munged": munge_answers,
        "slurmctld": lambda: "UP" in _command(["scontrol", "ping"], env, check=False).stdout,
        "slurmd": lambda: (node_states(env) or {}).get(node) in READY_STATES,
    }
    if not munge_answers():
        key = folder / "munge" / "munge.key"
        key.parent.mkdir(mode=0o755, exist_ok=True)
        key.write_bytes(os.urandom(1024))
        key.chmod(0o400)
        MUNGE_SOCKET.parent.mkdir(mode=0o755, parents=True, exist_ok=True)
        commands = {
            "munged": [
                "munged",
                "--foreground",  # then it logs to stderr: logs/munged.log
                "--force",  # as root, and past a stale socket
                f"--key-file={key}",
                f"--socket={MUNGE_SOCKET}",
                f"--pid-file={key.parent / 'munged.pid'}",
                f"--seed-file={key.parent / 'munged.seed'}",
            ],
            **commands,
        }
    try:
        for name, args in commands.items():
            # slurmctld and slurmd log to logs/NAME.log (slurm.conf); what they print before
            # they open it goes to logs/NAME.out.
            out = (logs / ("munged.log" if name == "munged" else f"{name}.out")).open("w")
            # A session of its own: a Ctrl-C of the test run does not reach the daemons first.
            cluster.processes[name] = subprocess.Popen(
                args, env=env, stdout=out, stderr=subprocess.STDOUT, start_new_session=True
            )
            out.close()
            _wait_for(name, ready[name], cluster, t0 + timeout)
    except BaseException:
        cluster.stop()
        raise
    cluster.start_seconds = time.perf_counter() - t0
    (folder / "pids").write_text("".join(f"{n} {p.pid}\n" for n, p in cluster.processes.items()))
    return cluster


def _wait_for(name: str, ready: Callable[[], bool], cluster: SlurmCluster, deadline: float) -> None:
    process = cluster.processes[name]
    logs = [cluster.log(name)] + ([] if name == "munged" else [cluster.log(name).with_suffix(".out")])
    where = " and ".join(map(str, logs))
    while True:
        if process.poll() is not None:
            raise ClusterError(
                f"SLURM test cluster: {name} exited with status {process.returncode} while starting; "
                f"read {where}:\n    {_tail(logs[-1])}"
            )
        if ready():
            return
        if time.perf_counter() > deadline:
            what = "the node did not become idle in sinfo" if name == "slurmd" else f"{name} did not answer"
            raise ClusterError(f"SLURM test cluster: {what} in time; read {where}:\n    {_tail(logs[0])}")
        time.sleep(0.2)


def cluster_for_tests(folder: Path) -> SlurmCluster:
    """The cluster running on this host, else a single-node one started in ``folder``.

    Raises :class:`SlurmUnavailable` when there is none and none can be started, and
    :class:`ClusterError` when starting one fails.
    """
    return running_cluster() or start_cluster(folder)


def stop_folder(folder: Path) -> None:
    """End the daemons of a cluster started by ``python tests/slurm_cluster.py start FOLDER``."""
    folder = Path(folder).resolve()
    pids = dict(line.split() for line in (folder / "pids").read_text().splitlines())
    env = {**os.environ, "SLURM_CONF": str(folder / "slurm.conf")}
    _command(["scancel", "--user", getpass.getuser()], env, check=False)
    for name in reversed(DAEMONS):
        if name in pids:
            with contextlib.suppress(ProcessLookupError):
                os.kill(int(pids[name]), signal.SIGTERM)
            time.sleep(0.5)
    _remove_conf_link(folder)


def main(argv: list[str]) -> int:
    if len(argv) != 2 or argv[0] not in ("start", "stop"):
        print("usage: python tests/slurm_cluster.py start|stop FOLDER", file=sys.stderr)
        return 2
    action, folder = argv
    try:
        if action == "stop":
            stop_folder(Path(folder))
            return 0
        cluster = running_cluster()
        if cluster is not None:
            print(f"# a SLURM cluster is running already (nodes {', '.join(cluster.nodes)})")
            return 0
        cluster = start_cluster(Path(folder))
    except ClusterError as exc:
        print(exc, file=sys.stderr)
        return 1
    print(f"# single-node SLURM up in {cluster.start_seconds:.1f} s; logs in {cluster.folder}/logs")
    print(f"export SLURM_CONF={cluster.env['SLURM_CONF']}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
