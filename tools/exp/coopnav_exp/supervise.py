"""Process supervision for runs: start with a log each, readiness, clean stop, no orphans.

A `Supervisor` owns the processes of one launch. Each starts with its output (stdout and stderr)
in a log file of its own and, on Linux, with the kernel's parent-death signal set to SIGTERM: a
launcher that dies, however it dies, leaves no daemon behind. `stop_all` sends SIGTERM to every
process still running (each daemon's shared runtime stops cleanly on it, the recorder flushes),
waits `grace_s`, then SIGKILLs the rest. `signals_stop()` turns SIGINT / SIGTERM of the
launcher into `Interrupted`, so that `with Supervisor()` stops everything before the launcher
exits with 128 + the signal.
"""

from __future__ import annotations

import contextlib
import ctypes
import select
import signal
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator, Mapping, Sequence

PR_SET_PDEATHSIG = 1


class Interrupted(Exception):
    """The launcher received SIGINT or SIGTERM."""

    def __init__(self, signum: int):
        super().__init__(f"interrupted by signal {signum}")
        self.signum = signum

    @property
    def exit_status(self) -> int:
        return 128 + self.signum


class StartError(RuntimeError):
    """A process did not come up (it died at start, or readiness timed out)."""


def _die_with_parent() -> None:  # pragma: no cover - runs in the child between fork and exec
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
    except (OSError, AttributeError):
        pass


@contextlib.contextmanager
def signals_stop() -> Iterator[None]:
    """Within: SIGINT and SIGTERM raise Interrupted (in the main thread); restored after."""

    def handler(signum: int, _frame: object) -> None:
        raise Interrupted(signum)

    old = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)


@dataclass
class Process:
    name: str
    cmd: list[str]
    log: Path
    popen: subprocess.Popen
    started_s: float = field(default_factory=time.monotonic)

    @property
    def pid(self) -> int:
        return self.popen.pid

    def alive(self) -> bool:
        return self.popen.poll() is None

    @property
    def returncode(self) -> int | None:
        return self.popen.poll()

    def log_tail(self, n: int = 10) -> list[str]:
        try:
            return self.log.read_text(errors="replace").splitlines()[-n:]
        except OSError:
            return []


class Supervisor:
    """The processes of one launch, by name (a name started again replaces its entry)."""

    def __init__(self, grace_s: float = 10.0):
        self.grace_s = grace_s
        self.procs: dict[str, Process] = {}
        self._all: list[Process] = []  # every process ever started, for stop_all

    def __enter__(self) -> "Supervisor":
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop_all()

    def start(self, name: str, cmd: Sequence[str], log: Path, *, append: bool = True,
              env: Mapping[str, str] | None = None, cwd: Path | None = None) -> Process:
        """Starts `cmd` with stdout and stderr in `log` (appended to: a restart adds to it)."""
        log.parent.mkdir(parents=True, exist_ok=True)
        with open(log, "ab" if append else "wb") as out:
            popen = subprocess.Popen(list(cmd), stdout=out, stderr=subprocess.STDOUT,
                                     stdin=subprocess.DEVNULL, preexec_fn=_die_with_parent,
                                     env=None if env is None else dict(env), cwd=cwd)
        p = Process(name, list(cmd), log, popen)
        self.procs[name] = p
        self._all.append(p)
        return p

    def dead(self, names: Sequence[str] | None = None) -> list[Process]:
        """The processes (of `names`, default all current ones) that are no longer running."""
        sel = self.procs.values() if names is None else [self.procs[n] for n in names]
        return [p for p in sel if not p.alive()]

    def kill(self, name: str, sig: int = signal.SIGKILL) -> int | None:
        """Sends `sig` to `name` and waits for it; returns its exit status."""
        p = self.procs[name]
        with contextlib.suppress(ProcessLookupError):
            p.popen.send_signal(sig)
        return p.popen.wait()

    def stop(self, procs: Sequence[Process]) -> None:
        running = [p for p in procs if p.alive()]
        for p in running:
            with contextlib.suppress(ProcessLookupError):
                p.popen.send_signal(signal.SIGTERM)
        deadline = time.monotonic() + self.grace_s
        for p in running:
            try:
                p.popen.wait(timeout=max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                with contextlib.suppress(ProcessLookupError):
                    p.popen.kill()
                p.popen.wait()

    def stop_all(self) -> None:
        """SIGTERM to every running process, SIGKILL after the grace; all reaped."""
        self.stop(self._all)
        self._all = [p for p in self._all if p.alive()]

    def start_waiter(self, waiter_cmd: Sequence[str], *, timeout_s: float = 60.0,
                     env: Mapping[str, str] | None = None) -> subprocess.Popen:
        """Starts `waiter_cmd` (`coopnav_ctl wait-ready NAMES --announce`) and returns once it
        printed its first line, i.e. listens: the daemons started after it cannot send their first
        status message unheard (the next one comes a status period later). A waiter that says
        nothing within `timeout_s` or exits first raises StartError with what it said."""
        waiter = subprocess.Popen(list(waiter_cmd), stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                                  preexec_fn=_die_with_parent,
                                  env=None if env is None else dict(env))
        assert waiter.stdout is not None
        listening = select.select([waiter.stdout], [], [], timeout_s)[0]
        if listening and waiter.stdout.readline():
            return waiter
        if waiter.poll() is None:
            waiter.kill()
        waiter.wait()
        err = waiter.stderr.read().decode(errors="replace").strip() if waiter.stderr else ""
        raise StartError(f"{' '.join(map(str, waiter_cmd[:2]))} did not start listening "
                         f"(status {waiter.returncode}){': ' + err if err else ''}")

    def wait_ready(self, waiter_cmd: Sequence[str] | subprocess.Popen, watched: Sequence[str],
                   *, poll_s: float = 0.1, log: Path | None = None,
                   env: Mapping[str, str] | None = None) -> None:
        """Runs `waiter_cmd` (e.g. `coopnav_ctl wait-ready NAMES --timeout-s T`; or waits for a
        waiter `start_waiter` started) while watching the processes `watched`: one that dies
        meanwhile (a bad config, map or scenario) raises StartError within `poll_s`, with its exit
        status and the end of its log, instead of after the waiter's timeout. Returns as soon as
        the waiter exits; a waiter that fails raises StartError with what it said."""
        out = open(log, "ab") if log else subprocess.DEVNULL
        try:
            if isinstance(waiter_cmd, subprocess.Popen):
                waiter, waiter_cmd = waiter_cmd, [str(a) for a in waiter_cmd.args]  # type: ignore[union-attr]
            else:
                waiter = subprocess.Popen(list(waiter_cmd), stdout=out, stderr=subprocess.STDOUT
                                          if log else subprocess.PIPE, stdin=subprocess.DEVNULL,
                                          preexec_fn=_die_with_parent,
                                          env=None if env is None else dict(env))
            try:
                while True:
                    try:
                        waiter.wait(timeout=poll_s)
                        break
                    except subprocess.TimeoutExpired:
                        pass
                    dead = self.dead(watched)
                    if dead:
                        d = dead[0]
                        tail = "\n".join(f"  {d.name}: {line}" for line in d.log_tail(10))
                        raise StartError(f"{d.name} exited at start (status {d.returncode}); "
                                         f"the end of {d.log}:\n{tail}")
            finally:
                if waiter.poll() is None:
                    waiter.kill()
                    waiter.wait()
            err = b"" if log or waiter.stderr is None else waiter.stderr.read()
            if waiter.stdout is not None and waiter.stdout is not out:
                waiter.stdout.close()
            if waiter.stderr is not None:
                waiter.stderr.close()
            if waiter.returncode != 0:
                raise StartError(f"{' '.join(map(str, waiter_cmd[:2]))} failed (status "
                                 f"{waiter.returncode}){': ' + err.decode(errors='replace').strip() if err else ''}")
        finally:
            if log:
                out.close()  # type: ignore[union-attr]


def wait_for_line(path: Path, text: str, timeout_s: float, check_s: float = 0.01) -> bool:
    """Returns True once a line of `path` contains `text` (at once when one does already), False
    after `timeout_s`: a condition checked, not a fixed sleep."""
    end = time.monotonic() + timeout_s
    while True:
        try:
            if text in path.read_text(errors="replace"):
                return True
        except OSError:
            pass
        if time.monotonic() >= end:
            return False
        time.sleep(check_s)


class Ports:
    """Consecutive udpm ports from a base, `stride` per run: a run takes its own port and the
    next stride - 1 (a lossy run's relays). Two launchers on one machine must be given bases
    apart (COOPNAV_RUN_PORT_BASE, COOPNAV_FAULT_PORT_BASE, the tests' COOPNAV_TEST_PORT_BASE)."""

    def __init__(self, base: int, stride: int = 1):
        if not 1024 <= base <= 65535 - stride:
            raise ValueError(f"port base {base} outside 1024..{65535 - stride}")
        self.next_port, self.stride = base, stride

    def take(self) -> int:
        p = self.next_port
        if p + self.stride > 65536:
            raise ValueError("out of udp ports")
        self.next_port += self.stride
        return p


def call_logged(cmd: Sequence[str], log: Path, check: bool = False,
                stdout_to: Path | None = None) -> int:
    """Runs `cmd` to its end: stdout to `stdout_to` (else the log), stderr to `log`."""
    log.parent.mkdir(parents=True, exist_ok=True)
    with open(log, "ab") as err, (open(stdout_to, "wb") if stdout_to else contextlib.nullcontext(err)) as out:
        rc = subprocess.call(list(cmd), stdout=out, stderr=err, stdin=subprocess.DEVNULL,
                             preexec_fn=_die_with_parent)
    if check and rc != 0:
        raise subprocess.CalledProcessError(rc, list(cmd))
    return rc

