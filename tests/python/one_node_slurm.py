"""A real one-node SLURM on this machine, for tests/python/test_slurm.py: munged,
slurmctld and slurmd (Debian's slurmctld, slurmd, slurm-client and munge, which
scripts/setup.sh installs), with their key, state, logs and sockets in a temporary folder,
a minimal slurm.conf and no accounting database.

The configuration is written to /etc/slurm/slurm.conf, the default path, and removed
again by stop(): snakemake-executor-plugin-slurm's job step drops every SLURM_* variable
(SLURM_CONF among them) before its srun, so a configuration anywhere else is not found
inside a job. An existing slurm.conf that this module did not write is never replaced.

The node claims 320 CPUs and 500 GB (SlurmdParameters=config_overrides): enough for the
profile's requests (16 CPUs a run) of all 16 runs of config/ci.yaml at once, so that the
workflow goes through SLURM in as few rounds of the plugin's polling as its dependencies
allow; nothing enforces them here (no cgroups: proctrack/linuxproc, task/none), so the
jobs share the machine's cores. Two partitions: `main` (the default, no time limit) and
`short` (a limit of SHORT_MINUTES, one minute: SLURM's smallest).

Without a database, squeue and scontrol know finished jobs for MinJobAge (an hour here,
longer than the tests' workflows take even on a loaded machine: at 600 s a run of the
tests beside other heavy work lost its jobs before the plugin or the test read them): the
plugin's status command is `squeue` and the test reads the jobs with `scontrol`."""

import fcntl
import os
import secrets
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from pathlib import Path

CONF = Path("/etc/slurm/slurm.conf")
# One cluster at a time on a machine (one slurm.conf): a second test waits for the first.
LOCK = Path(tempfile.gettempdir()) / "capsule-rheology-one-node-slurm.lock"
LOCK_WAIT = 900
MARK = "# written by tests/python/one_node_slurm.py: removed when its test ends\n"
TOOLS = ("munged", "slurmctld", "slurmd", "sbatch", "srun", "squeue", "scontrol", "sinfo")
NODE_CPUS = 320
SHORT_MINUTES = 1


class ClusterError(RuntimeError):
    """The cluster could not start; the message says why."""


def environment():
    """This process's environment without SLURM's job variables (a CI job that itself
    runs under SLURM would otherwise point the clients at its own cluster)."""
    return {k: v for k, v in os.environ.items()
            if not k.startswith(("SLURM_", "SBATCH_", "SRUN_", "SQUEUE_"))}


def free_ports(n):
    """n distinct free TCP ports (all held open together while they are chosen)."""
    sockets = [socket.socket() for _ in range(n)]
    try:
        for s in sockets:
            s.bind(("127.0.0.1", 0))
        return [s.getsockname()[1] for s in sockets]
    finally:
        for s in sockets:
            s.close()


def which(tool):
    """The tool's path (daemons live in /usr/sbin, which a user's PATH may lack)."""
    return shutil.which(tool) or shutil.which(tool, path="/usr/sbin:/sbin:/usr/bin")


def tail(path, lines=15):
    try:
        return "".join(Path(path).read_text(errors="replace").splitlines(True)[-lines:])
    except OSError:
        return "(no log)\n"


class OneNodeSlurm:
    def __init__(self, folder):
        self.dir = Path(folder)
        self.host = socket.gethostname().split(".")[0]
        self.pids = {}
        self.lock = None

    def path(self, name):
        return self.dir / name

    def check_preconditions(self):
        missing = [t for t in TOOLS if which(t) is None]
        if missing:
            raise ClusterError(f"not installed: {' '.join(missing)} (Debian packages "
                               "slurmctld slurmd slurm-client munge; bash scripts/setup.sh "
                               "installs them)")
        if os.geteuid() != 0:
            raise ClusterError("not root: slurmd must run as root to start jobs")
        if CONF.exists() and not CONF.read_text(errors="replace").startswith(MARK):
            raise ClusterError(f"{CONF} exists and was not written by this test (a SLURM "
                               "installation of this machine): not replaced")

    def start(self):
        self.take_lock()
        self.check_preconditions()
        for sub in ("munge", "state", "spool", "log"):
            self.path(sub).mkdir(parents=True, exist_ok=True)
        self.start_munge()
        self.write_conf()
        self.daemon("slurmctld", [which("slurmctld"), "-c"])
        self.daemon("slurmd", [which("slurmd")])
        self.wait_for_node()

    def take_lock(self):
        """Waits until no other cluster of these tests runs here (stop() releases it)."""
        lock = open(LOCK, "w")
        for _ in range(LOCK_WAIT):
            try:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
                self.lock = lock
                return
            except BlockingIOError:
                time.sleep(1)
        lock.close()
        raise ClusterError(f"another one-node SLURM of these tests has held {LOCK} for "
                           f"{LOCK_WAIT} s: not started beside it")

    def start_munge(self):
        key = self.path("munge/munge.key")
        key.write_bytes(secrets.token_bytes(1024))
        key.chmod(0o600)
        # A munged of its own (key, socket, seed in the folder), beside any of the system.
        self.daemon("munged", [which("munged"), "--force",
                               f"--socket={self.path('munge/socket')}", f"--key-file={key}",
                               f"--log-file={self.path('log/munged.log')}",
                               f"--pid-file={self.path('munged.pid')}",
                               f"--seed-file={self.path('munge/seed')}"])

    def write_conf(self):
        """The node by its short host name at 127.0.0.1 (no name resolution needed); root
        runs everything; no cgroups (linuxproc tracks a job's processes); finished jobs
        kept 600 s; at a time limit SIGTERM, then SIGKILL 5 s later (KillWait); a job's
        processes as nice as the sbatch that submitted it (PropagatePrioProcess)."""
        d = self.dir
        ctld_port, d_port = free_ports(2)
        CONF.parent.mkdir(parents=True, exist_ok=True)
        CONF.write_text(MARK + f"""ClusterName=capsimtest
SlurmctldHost={self.host}(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket={d}/munge/socket
CredType=cred/munge
SlurmctldPort={ctld_port}
SlurmdPort={d_port}
StateSaveLocation={d}/state
SlurmdSpoolDir={d}/spool
SlurmctldPidFile={d}/slurmctld.pid
SlurmdPidFile={d}/slurmd.pid
SlurmctldLogFile={d}/log/slurmctld.log
SlurmdLogFile={d}/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MinJobAge=3600
KillWait=5
PropagatePrioProcess=1
SlurmdParameters=config_overrides
NodeName={self.host} NodeAddr=127.0.0.1 CPUs={NODE_CPUS} RealMemory=500000 State=UNKNOWN
PartitionName=main Nodes={self.host} Default=YES MaxTime=UNLIMITED State=UP
PartitionName=short Nodes={self.host} MaxTime={SHORT_MINUTES} State=UP
""")

    def daemon(self, name, cmd):
        """Starts a daemon (each forks and writes its pid file) or says why it did not."""
        proc = subprocess.run(cmd, capture_output=True, text=True, env=environment(),
                              timeout=60)
        pid_file = self.path(f"{name}.pid")
        for _ in range(100):
            if pid_file.exists() and pid_file.read_text().strip():
                self.pids[name] = int(pid_file.read_text())
                return
            time.sleep(0.1)
        raise ClusterError(f"{name} did not start (exit {proc.returncode}): "
                           f"{proc.stderr.strip()}\n{self.logs()}")

    def wait_for_node(self, seconds=60):
        state = ""
        for _ in range(seconds * 2):
            if not all(alive(pid) for pid in self.pids.values()):
                break
            state = self.run("sinfo", "-h", "-n", self.host, "-o", "%T", check=False).stdout
            if state.strip() in ("idle", "mixed", "allocated"):
                return
            time.sleep(0.5)
        raise ClusterError(f"node {self.host} not ready (state '{state.strip()}', daemons "
                           f"alive: {[n for n, p in self.pids.items() if alive(p)]})\n"
                           f"{self.logs()}")

    def logs(self):
        return "".join(f"--- {name} ---\n{tail(self.path(f'log/{name}.log'))}"
                       for name in ("munged", "slurmctld", "slurmd"))

    def run(self, *cmd, check=True):
        return subprocess.run(list(cmd), capture_output=True, text=True, check=check,
                              env=environment(), timeout=60)

    def jobs(self):
        """Every job slurmctld knows, as {field: value} (scontrol show job -o)."""
        out = self.run("scontrol", "-o", "show", "job").stdout
        return [dict(word.split("=", 1) for word in line.split() if "=" in word)
                for line in out.splitlines() if line.startswith("JobId=")]

    def stop(self):
        """Cancels every job, stops the daemons and removes the configuration."""
        if "slurmctld" in self.pids:
            self.run("scancel", "--full", "--user=root", check=False)
        for name in ("slurmd", "slurmctld", "munged"):
            if name in self.pids:
                terminate(self.pids.pop(name))
        if self.lock is None:
            return
        if CONF.exists() and CONF.read_text(errors="replace").startswith(MARK):
            CONF.unlink()
        self.lock.close()  # releases the lock
        self.lock = None


def alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # A daemon of ours that exited but is not reaped yet counts as gone.
    try:
        return Path(f"/proc/{pid}/stat").read_text().split()[2] != "Z"
    except OSError:
        return False


def terminate(pid, seconds=10):
    """SIGTERM, then SIGKILL if the process is still there after `seconds`."""
    try:
        os.kill(pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    for _ in range(seconds * 10):
        if not alive(pid):
            return
        time.sleep(0.1)
    os.kill(pid, signal.SIGKILL)
