"""A job pool: N runs at a time, each on an LCM port of its own and in a process group of its own.

A run is a command (a worker process that starts the run's daemons as its children). The pool
gives each running job a slot k in 0..N-1 and with it the port `port_base + k`, so two runs at the
same time never share a bus (udpm with ttl=0: nothing leaves the host). A run that outlives its wall
timeout is stopped with its daemons: SIGTERM to its whole process group (the worker's own handler
stops the daemons it started), SIGKILL to the group `kill_after_s` later. When the pool itself is
interrupted (SIGINT, SIGTERM) it stops every running job the same way before it returns.

Results are given back in the order the jobs were given, whatever order they finished in.
"""

from __future__ import annotations

import dataclasses
import os
import select
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable, Mapping, Sequence


@dataclasses.dataclass(frozen=True)
class Job:
    """One run: `command(port)` is its argv; its output goes to `log` (appended)."""

    name: str
    command: Callable[[int], Sequence[str]]
    log: Path
    env: Mapping[str, str] | None = None  # None: the pool's environment


@dataclasses.dataclass(frozen=True)
class Finished:
    """What became of a job: its exit status (negative: the signal that ended it), whether the
    wall timeout stopped it, the slot and port it ran on and its wall time [s]."""

    job: Job
    returncode: int
    timed_out: bool
    slot: int
    port: int
    wall_s: float


@dataclasses.dataclass
class _Running:
    job: Job
    index: int
    slot: int
    port: int
    proc: subprocess.Popen
    start_s: float
    term_sent_s: float | None = None
    timed_out: bool = False


def _signal_group(proc: subprocess.Popen, sig: int) -> None:
    try:
        os.killpg(proc.pid, sig)
    except ProcessLookupError:
        pass


class Pool:
    """Runs jobs `jobs` at a time on ports `port_base + slot`."""

    def __init__(self, jobs: int, port_base: int, timeout_s: float, kill_after_s: float = 20.0,
                 poll_s: float = 0.1) -> None:
        if jobs < 1:
            raise ValueError(f"jobs must be positive, not {jobs}")
        self.jobs = jobs
        self.port_base = port_base
        self.timeout_s = timeout_s
        self.kill_after_s = kill_after_s
        self.poll_s = poll_s

    def run(self, jobs: Sequence[Job],
            on_finished: Callable[[Finished, int, int], None] | None = None) -> list[Finished]:
        """Runs every job; `on_finished(result, done, total)` after each one ends. Returns the
        results in the order of `jobs`. SIGINT / SIGTERM stop the running jobs, then raise
        KeyboardInterrupt (SIGINT) or SystemExit(143) (SIGTERM)."""
        results: list[Finished | None] = [None] * len(jobs)
        free = list(range(self.jobs))
        running: list[_Running] = []
        pending = list(enumerate(jobs))
        done = 0
        stopping: list[int] = []

        def on_signal(signum: int, _frame) -> None:
            stopping.append(signum)

        previous = {}
        in_main_thread = _is_main_thread()
        if in_main_thread:
            for sig in (signal.SIGINT, signal.SIGTERM):
                previous[sig] = signal.signal(sig, on_signal)
        try:
            while pending or running:
                if stopping:
                    self._stop_all(running)
                    if stopping[0] == signal.SIGINT:
                        raise KeyboardInterrupt
                    raise SystemExit(143)
                while pending and free:
                    index, job = pending.pop(0)
                    slot = free.pop(0)
                    running.append(self._start(job, index, slot))
                now = time.monotonic()
                for r in list(running):
                    rc = r.proc.poll()
                    if rc is None:
                        self._enforce_timeout(r, now)
                        continue
                    running.remove(r)
                    free.append(r.slot)
                    free.sort()
                    res = Finished(r.job, rc, r.timed_out, r.slot, r.port, now - r.start_s)
                    results[r.index] = res
                    done += 1
                    if on_finished is not None:
                        on_finished(res, done, len(jobs))
                if running:
                    _wait_any([r.proc for r in running], self.poll_s)
        finally:
            if running:
                self._stop_all(running)
            for sig, handler in previous.items():
                signal.signal(sig, handler)
        return [r for r in results if r is not None]

    def _start(self, job: Job, index: int, slot: int) -> _Running:
        port = self.port_base + slot
        job.log.parent.mkdir(parents=True, exist_ok=True)
        with open(job.log, "ab") as log:
            proc = subprocess.Popen(list(job.command(port)), stdin=subprocess.DEVNULL, stdout=log,
                                    stderr=subprocess.STDOUT, start_new_session=True,
                                    env=dict(job.env) if job.env is not None else None)
        return _Running(job, index, slot, port, proc, time.monotonic())

    def _enforce_timeout(self, r: _Running, now: float) -> None:
        if r.term_sent_s is None and now - r.start_s > self.timeout_s:
            r.timed_out = True
            r.term_sent_s = now
            _signal_group(r.proc, signal.SIGTERM)
        elif r.term_sent_s is not None and now - r.term_sent_s > self.kill_after_s:
            _signal_group(r.proc, signal.SIGKILL)

    def _stop_all(self, running: list[_Running]) -> None:
        for r in running:
            _signal_group(r.proc, signal.SIGTERM)
        deadline = time.monotonic() + self.kill_after_s
        for r in running:
            try:
                r.proc.wait(timeout=max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                _signal_group(r.proc, signal.SIGKILL)
                r.proc.wait()
        running.clear()


def _wait_any(procs: Sequence[subprocess.Popen], timeout_s: float) -> None:
    """Returns once one of `procs` exits (its pidfd turns readable) or after `timeout_s`: the next
    job starts when a slot frees, not at the next poll. Without pidfds (Linux < 5.3), a sleep."""
    fds: list[int] = []
    try:
        for p in procs:
            fds.append(os.pidfd_open(p.pid))
        select.select(fds, [], [], timeout_s)
    except (OSError, AttributeError):
        time.sleep(timeout_s)
    finally:
        for fd in fds:
            os.close(fd)


def _is_main_thread() -> bool:
    import threading
    return threading.current_thread() is threading.main_thread()


class Progress:
    """One line per finished run, as scripts/population.sh has always printed it:
    `[k/n] name  STATE  sim 41.2 s  wall 9.3 s  ETA 1m40s` (runs done / all, the run's final
    state, its simulated time, its wall time, and the time left at the mean wall time per finished
    run so far). On a terminal the line is rewritten in place; piped, each stays on its own."""

    def __init__(self, total: int, stream=None, start_s: float | None = None) -> None:
        self.total = total
        self.stream = stream if stream is not None else sys.stdout
        self.start_s = time.monotonic() if start_s is None else start_s
        self.tty = self.stream.isatty()

    def line(self, done: int, name: str, state: str, sim_s: float | None, wall_s: float,
             now_s: float | None = None) -> str:
        now = time.monotonic() if now_s is None else now_s
        eta = (now - self.start_s) / done * (self.total - done)
        sim = "-" if sim_s is None else f"{sim_s:.1f} s"
        return (f"[{done}/{self.total}] {name:<16} {state:<19} sim {sim:<8} "
                f"wall {wall_s:6.1f} s  ETA {int(eta / 60)}m{int(eta) % 60:02d}s")

    def show(self, done: int, name: str, state: str, sim_s: float | None, wall_s: float) -> None:
        text = self.line(done, name, state, sim_s, wall_s)
        if self.tty:
            self.stream.write("\r" + text + "\033[K")
        else:
            self.stream.write(text + "\n")
        self.stream.flush()

    def end(self) -> None:
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()
