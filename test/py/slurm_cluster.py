"""A single-node Slurm cluster on this machine's loopback, for tests: munged, slurmctld and slurmd
with a generated slurm.conf, everything (key, sockets, state, logs) in one temporary folder.

`SlurmCluster.why_not()` says why one cannot be started here (None when it can); `start()` waits
until the node is idle; `env()` is what a client (sbatch, squeue) needs; `stop()` ends the three
daemons it started (by their pids) and nothing else.
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import time
from pathlib import Path

DAEMONS = ("munged", "mungekey", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo")


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _which(name: str) -> str | None:
    return shutil.which(name) or next(
        (str(p) for p in (Path("/usr/sbin") / name, Path("/sbin") / name) if p.exists()), None)


class SlurmCluster:
    def __init__(self, root: Path, cpus: int | None = None) -> None:
        self.root = root
        self.cpus = cpus or os.cpu_count() or 1
        self.host = socket.gethostname()
        self.procs: list[subprocess.Popen] = []

    @staticmethod
    def why_not() -> str | None:
        missing = [d for d in DAEMONS if _which(d) is None]
        if missing:
            return f"no {', '.join(missing)} (Debian: slurm-wlm, munge)"
        if os.geteuid() != 0:
            return "slurmd runs jobs as their users: it needs root"
        return None

    @property
    def conf(self) -> Path:
        return self.root / "slurm.conf"

    @property
    def munge_socket(self) -> Path:
        return self.root / "munge" / "munge.socket"

    def env(self) -> dict[str, str]:
        env = dict(os.environ)
        env["SLURM_CONF"] = str(self.conf)
        return env

    def write_conf(self) -> None:
        r = self.root
        for d in ("state", "spool", "log"):
            (r / d).mkdir(parents=True, exist_ok=True)
        # A container has no cgroups to give Slurm: process tracking by /proc, no task plugin.
        self.conf.write_text(f"""ClusterName=coopnavtest
SlurmctldHost={self.host}(127.0.0.1)
SlurmctldPort={_free_port()}
SlurmdPort={_free_port()}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={self.munge_socket}
StateSaveLocation={r / 'state'}
SlurmdSpoolDir={r / 'spool'}
SlurmctldPidFile={r / 'slurmctld.pid'}
SlurmdPidFile={r / 'slurmd.pid'}
SlurmctldLogFile={r / 'log' / 'slurmctld.log'}
SlurmdLogFile={r / 'log' / 'slurmd.log'}
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
NodeName={self.host} NodeAddr=127.0.0.1 CPUs={self.cpus} State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
""")

    def _spawn(self, name: str, argv: list[str]) -> None:
        log = open(self.root / "log" / f"{name}.out", "wb")
        self.procs.append(subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT,
                                           stdin=subprocess.DEVNULL, env=self.env()))

    def start(self, timeout_s: float = 30.0) -> None:
        self.write_conf()
        m = self.root / "munge"
        m.mkdir(mode=0o700, exist_ok=True)
        subprocess.run([_which("mungekey"), "-c", "-k", str(m / "munge.key")], check=True,
                       capture_output=True)
        os.chmod(m / "munge.key", 0o600)
        self._spawn("munged", [_which("munged"), "-F", "-f", f"--key-file={m / 'munge.key'}",
                               f"--socket={self.munge_socket}", f"--pid-file={m / 'munged.pid'}",
                               f"--log-file={m / 'munged.log'}",
                               f"--seed-file={m / 'munged.seed'}"])
        self._wait(lambda: self.munge_socket.exists(), timeout_s, "munged")
        self._spawn("slurmctld", [_which("slurmctld"), "-D", "-f", str(self.conf)])
        self._spawn("slurmd", [_which("slurmd"), "-D", "-f", str(self.conf), "-N", self.host])
        self._wait(self._idle, timeout_s, "the node to be idle")

    def _idle(self) -> bool:
        p = subprocess.run([_which("sinfo"), "-h", "-o", "%t"], env=self.env(),
                           capture_output=True, text=True, check=False)
        return p.returncode == 0 and p.stdout.strip() == "idle"

    def _wait(self, ready, timeout_s: float, what: str) -> None:
        deadline = time.monotonic() + timeout_s
        while not ready():
            for p in self.procs:
                if p.poll() is not None:
                    raise RuntimeError(f"{p.args[0]} exited {p.returncode} while waiting for "
                                       f"{what}: {self.logs()}")
            if time.monotonic() > deadline:
                raise RuntimeError(f"no {what} after {timeout_s} s: {self.logs()}")
            time.sleep(0.2)

    def logs(self) -> str:
        out = []
        for f in sorted((self.root / "log").glob("*")):
            out.append(f"--- {f.name}\n" + "\n".join(f.read_text(errors="replace")
                                                      .splitlines()[-10:]))
        return "\n".join(out)

    def stop(self) -> None:
        for p in reversed(self.procs):
            if p.poll() is None:
                p.terminate()
        for p in reversed(self.procs):
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        self.procs.clear()
