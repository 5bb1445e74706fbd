"""Where a run's wall time goes: run_one's phases (DIR/timing.json) and a population's breakdown.

run_one marks the wall time (time.time()) at each of its steps in a `Timeline`; the world's own
log adds when the simulation ran ("running '<name>'" to "'<name>' ended at"), and each daemon's
log when it said it is ready (from its start: process start-up, config and map load, e.g. the
distance server's octree). `Timeline.write` turns them into DIR/timing.json:

  phases_s: consecutive phases that add up to total_s:
    launch          run_one's start to the last daemon started (recorder and waiter first)
    daemons_ready   to every daemon's first status message (its config, map and distance field)
    recorder_ready  to the recorder's subscription confirmed (its log line)
    world_ready     world_sim started to its first step (its start-up and the participants'
                    status heard)
    simulation      the first step to the end (world_sim's own log)
    world_exit      the end to world_sim's exit seen
    after           the `after` hook
    stop            the recorder flushed and every process stopped
    summarize       coopnav_ctl summarize
    other           what is left (run_one's own Python)
  ready_s: per daemon, its start to its "ready" log line.

Wall times only: no result depends on them, and they are kept out of every table.

  python3 -m coopnav_exp.timing DIR   the breakdown of a population folder (DIR/runs/*), or of
                                      one run folder, as text and `key value` lines
A population folder without timing.json files (a launcher from before them) still gives each
run's wall time (its worker log's stamps) and its simulation (world_sim's log).
"""

from __future__ import annotations

import json
import re
import sys
import time
from pathlib import Path
from typing import Iterable

PHASES = ("launch", "daemons_ready", "recorder_ready", "world_ready", "simulation",
          "world_exit", "after", "stop", "summarize", "other")

# "[2026-12-07 15:07:43.787] [coopnav:15733] [info] ..." (daemons/common/runtime/log.cpp) and
# "[2026-12-07 15:07:43.787] worker: ..." (population.worker_main).
_STAMP = re.compile(r"^\[(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d)\.(\d{3})\]")


def stamp_s(line: str) -> float | None:
    """The wall time (seconds since the epoch) a log line is stamped with (local time, ms)."""
    m = _STAMP.match(line)
    if not m:
        return None
    return time.mktime(time.strptime(m.group(1), "%Y-%m-%d %H:%M:%S")) + int(m.group(2)) / 1e3


def first_stamp(path: Path, needle: str) -> float | None:
    """The stamp of the first line of `path` that contains `needle` (None: none, or no file)."""
    try:
        with open(path, errors="replace") as f:
            for line in f:
                if needle in line:
                    return stamp_s(line)
    except OSError:
        pass
    return None


def world_span(run_dir: Path, world: str = "world_sim") -> tuple[float | None, float | None]:
    """When the world's first step and its end were logged (wall seconds)."""
    log = run_dir / f"{world}.log"
    return first_stamp(log, f"{world}: running '"), first_stamp(log, "' ended at t = ")


class Timeline:
    """run_one's marks: `mark(name)` stamps the wall time of a step once it is done."""

    def __init__(self) -> None:
        self.t0 = time.time()
        self.marks: dict[str, float] = {}
        self.spawned: dict[str, float] = {}  # daemon -> when it was started

    def mark(self, name: str) -> None:
        self.marks[name] = time.time()

    def phases(self, run_dir: Path, world: str = "world_sim") -> dict:
        m = dict(self.marks)
        end = m.get("summarized") or m.get("stopped") or time.time()
        running, ended = world_span(run_dir, world)
        # A phase whose end is unknown (a run that failed at start) ends where the next begins.
        points = [("launch", m.get("spawned")), ("daemons_ready", m.get("ready")),
                  ("recorder_ready", m.get("recorder_ready")),
                  ("world_ready", running), ("simulation", ended),
                  ("world_exit", m.get("world_exited")), ("after", m.get("after")),
                  ("stop", m.get("stopped")), ("summarize", m.get("summarized"))]
        phases = dict.fromkeys(PHASES, 0.0)
        last = self.t0
        for name, t in points:
            if t is None or t < last:
                continue
            phases[name] = t - last
            last = t
        total = max(end, last) - self.t0
        phases["other"] = max(0.0, total - sum(phases.values()))
        ready = {}
        for d, t in self.spawned.items():
            r = first_stamp(run_dir / f"{d}.log", f"{d}: ready (pid")
            if r is not None:
                ready[d] = round(max(0.0, r - t), 3)
        return {"total_s": round(total, 3),
                "phases_s": {k: round(v, 3) for k, v in phases.items()},
                "ready_s": ready}

    def write(self, run_dir: Path, world: str = "world_sim") -> dict:
        doc = self.phases(run_dir, world)
        (run_dir / "timing.json").write_text(json.dumps(doc, indent=1) + "\n")
        return doc


# ---- a population's breakdown


def run_timing(run_dir: Path, worker_log: Path | None = None) -> dict | None:
    """A run's timing.json; without one, its total (worker log stamps) and simulation only."""
    try:
        return json.loads((run_dir / "timing.json").read_text())
    except (OSError, ValueError):
        pass
    running, ended = world_span(run_dir)
    if worker_log is None or running is None or ended is None:
        return None
    total = worker_wall_s(worker_log)
    if total is None:
        return None
    return {"total_s": total, "phases_s": {"simulation": ended - running}, "ready_s": {}}


def breakdown(runs: Iterable[dict]) -> dict:
    """Sums over runs: their count, total wall, each phase, the mean per daemon's ready time."""
    runs = list(runs)
    out = {"runs": len(runs), "total_s": sum(r["total_s"] for r in runs),
           "phases_s": {p: sum(r["phases_s"].get(p, 0.0) for r in runs) for p in PHASES},
           "detailed": all(set(PHASES) <= set(r["phases_s"]) for r in runs) and bool(runs)}
    names = sorted({d for r in runs for d in r.get("ready_s", {})})
    out["ready_mean_s"] = {
        d: sum(r["ready_s"][d] for r in runs if d in r["ready_s"])
        / max(1, sum(1 for r in runs if d in r["ready_s"])) for d in names}
    return out


def worker_wall_s(worker_log: Path) -> float | None:
    """A population worker's wall time from its log's stamps (its run and what it does around)."""
    start = first_stamp(worker_log, " on port ")
    done = first_stamp(worker_log, " done, world_sim exit")
    return None if start is None or done is None else done - start


def population_breakdown(pop_dir: Path) -> dict:
    runs, workers = [], 0.0
    for run_dir in sorted((pop_dir / "runs").iterdir()) if (pop_dir / "runs").is_dir() else []:
        log = pop_dir / "workers" / f"{run_dir.name}.log"
        t = run_timing(run_dir, log)
        if t is not None:
            runs.append(t)
        workers += worker_wall_s(log) or 0.0
    if not runs and (pop_dir / "timing.json").is_file():
        runs.append(run_timing(pop_dir))
    b = breakdown(runs)
    b["worker_wall_s"] = workers
    return b


def format_breakdown(b: dict) -> str:
    n, total = b["runs"], b["total_s"]
    if n == 0 or total <= 0:
        return "no run timings\n"
    lines = [f"{n} runs, {total / n:.2f} s wall each on average "
             f"({'run_one phases' if b['detailed'] else 'worker stamps and world log only'}):"]
    for p in PHASES:
        v = b["phases_s"][p]
        if b["detailed"] or p == "simulation":
            lines.append(f"  {p:<15} {v / n:7.3f} s  {100 * v / total:5.1f} %")
    if not b["detailed"]:
        rest = total - b["phases_s"]["simulation"]
        lines.append(f"  {'not simulation':<15} {rest / n:7.3f} s  {100 * rest / total:5.1f} %")
    for d, v in b["ready_mean_s"].items():
        lines.append(f"  ready after start: {d:<26} {v:6.3f} s")
    lines.append(f"simulation_share {b['phases_s']['simulation'] / total:.4f}")
    lines.append(f"run_wall_mean_s {total / n:.3f}")
    if b.get("worker_wall_s"):
        lines.append(f"worker_wall_sum_s {b['worker_wall_s']:.3f}")
    for p in PHASES:
        if b["detailed"]:
            lines.append(f"phase_mean_s.{p} {b['phases_s'][p] / n:.4f}")
    return "\n".join(lines) + "\n"


def main(argv: list[str]) -> int:
    if len(argv) != 1 or not Path(argv[0]).is_dir():
        print("usage: python3 -m coopnav_exp.timing DIR (a population or run folder)",
              file=sys.stderr)
        return 2
    sys.stdout.write(format_breakdown(population_breakdown(Path(argv[0]))))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
