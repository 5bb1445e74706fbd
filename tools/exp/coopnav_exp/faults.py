"""Fault runs of the paper's scenarios (README "Faults"): kills, an absent distance server, loss.

For each scenario:
  clean    one run as `scripts/coopnav run` does it: the reference decisions;
  kill     for each daemon, kill -9 at a random step (seeded, printed) and start it again with
           its restart journal; the run must complete, no daemon may die on its own, the
           decisions must be the clean ones or the run must say they are degraded, and there
           must be no dock the clean run did not have;
  absent   the distance server absent for the whole run: the run completes without a collision,
           the situations say the obstacle distances are unknown, and every dock is a
           precautionary one ("degraded: precautionary dock", dialogue_manager README);
  loss     10 % of every message between every two processes dropped (coopnav_lossy_relay):
           the decisions must be the clean ones.
Decisions (from each run's summary.json, `coopnav_ctl summarize`): what the robot said and did
to each human (say, action, recorder entries), the final CMs and how the run ended.
Prints one line per run and a table; writes everything under OUT (default runs/faults-<UTC>).

  scripts/coopnav faults [--out DIR] [--no-build] [--seed N] [--loss P]
                         [--scenarios "open_minimal ..."] [--kill "band_source ..."]
                         [--kills-per-scenario N] [--no-absent] [--no-loss] [--no-kill]
                         [--loss-seed N] [--absent-in "narrow_minimal ..."]
  (scripts/faults.sh takes the same options.)
  --kills-per-scenario N: N daemons per scenario (the --kill list in turn across scenarios);
  default: every daemon in every scenario.
  --loss-seed N: the relay's seed of every loss run (default: drawn from --seed).
  --absent-in LIST: the absent run only for these scenarios (default: every one).
Environment: COOPNAV_FAULT_SEED (the default --seed), COOPNAV_FAULT_PORT_BASE (7700; ten ports
per run), COOPNAV_NETNS_PREFIX / COOPNAV_NETNS_NETEM (every process on a host of its own,
scripts/multihost.sh).
Exit status: 0 every run complete with the same or explicitly degraded decisions and no false
dock; 1 a FAIL; 2 bad arguments.
"""

from __future__ import annotations

import argparse
import datetime
import os
import random
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from . import run as run_mod, supervise, system as system_mod
from .supervise import Interrupted

# A restarted band source rebuilds its planner memory by planning every recorded step again: the
# peers' step gates and the world wait for it instead of going on degraded. Liveness only.
PATIENT_ARGS = {
    "band_source": ["--set", "step_gate_timeout_s=60"],
    "situation_assessor": ["--set", "gate_timeout_ms=60000"],
    "path_assessor": ["--set", "gate_timeout_ms=60000"],
    "dialogue_manager": ["--set", "gate_timeout_ms=60000"],
}
# Absent server: every answer is missing anyway; one short attempt per step instead of the
# default 150 ms bound changes how long each step waits (67 s -> ~12 s a run), never what is
# decided.
ABSENT_ARGS = {"situation_assessor": ["--set", "distance_timeout_ms=20",
                                      "--set", "distance_attempts=1"]}
# Loss: the server is there; its bounded wait is 400 ms in ten attempts, so that a lost request
# or reply is asked again in time (a late answer to an earlier attempt still counts) and a slow
# answer on a loaded machine is not taken for an absent server. Most steps lose a message
# somewhere: world_sim re-publishes sooner than its default 0.25 s (wall clock only).
LOSS_ARGS = {"situation_assessor": ["--set", "distance_timeout_ms=40",
                                    "--set", "distance_attempts=10"],
             "world_sim": ["--set", "retransmit_period_s=0.02"]}
# A restarted band source re-plans every journaled step before it answers: on a loaded machine
# that can take longer than the scenario's step timeout. The world waits longer (liveness only).
KILL_STEP_TIMEOUT_S = 180


# ---- decisions and verdicts (pure: tested in test/py/test_faults.py) ----

def _r(v: Any, nd: int) -> Any:
    """A number as the transcript prints it (nd decimals); anything else as it is."""
    return round(v, nd) if isinstance(v, float) else v


def decisions(entry: dict) -> list[tuple]:
    """What the robot said and did, the final CMs and the end of the run, from a summary.json
    scenario entry, at the transcript's precision. Comparable between two runs."""
    out: list[tuple] = []
    for h in entry.get("humans") or []:
        hid = h.get("id")
        for e in h.get("transcript") or []:
            kind = e.get("kind")
            if kind == "say":
                out.append((_r(e.get("t_s"), 2), hid, _r(e.get("t_cross_s"), 2), "SAY",
                            e.get("act"), e.get("text"), e.get("round"), e.get("direction"),
                            e.get("delivery")))
            else:
                out.append((_r(e.get("t_s"), 2), hid, _r(e.get("t_cross_s"), 2), kind.upper(),
                            e.get("action") or e.get("command"), e.get("reason")))
    for h in entry.get("humans") or []:
        out.append(("FINAL CM", h.get("id"), _r(h.get("cm_window_m"), 3),
                    h.get("window_samples"), h.get("is_contributing"),
                    _r(h.get("cm_interaction_m"), 3), h.get("interaction_samples"),
                    h.get("is_contributing_interaction"), _r(h.get("gamma"), 2),
                    _r(h.get("tau_m"), 2)))
    out.append(("SIM", entry.get("final_state"), entry.get("last_step"),
                _r(entry.get("min_clearance_m"), 3), _r(entry.get("robot_time_to_goal_s"), 2)))
    return out


def docks(entry: dict, *, degraded: bool | None = None) -> set[int]:
    """The humans the robot docked for (only the degraded / not degraded docks if given)."""
    out = set()
    for h in entry.get("humans") or []:
        for e in h.get("transcript") or []:
            if e.get("kind") == "action" and e.get("action") == "DOCK" and (
                    degraded is None or bool(e.get("degraded")) == degraded):
                out.add(h.get("id"))
    return out


def _faults(entry: dict) -> dict:
    return entry.get("faults") or {}


def says_degraded(entry: dict, clean: dict) -> str | None:
    """Why the run's decisions may differ, as it says it itself: a restart without its state,
    more crossings with unknown obstacle distances than the clean run (the distance server not
    answering within its bound), a precautionary dock. None when it says nothing of the kind."""
    f, fc = _faults(entry), _faults(clean)
    lost = [r for r in f.get("restarts") or [] if not r.get("recovered")]
    why = []
    if lost:
        r = lost[0]
        why.append(f"degraded: {r.get('participant')} restarted at step {r.get('step')}, "
                   f"{r.get('note')}")
    if (f.get("crossing_distance_unknown") or 0) > (fc.get("crossing_distance_unknown") or 0):
        why.append("distance server: obstacle distances unknown at "
                   f"{f['crossing_distance_unknown']} crossing situations")
    if docks(entry, degraded=True):
        why.append("precautionary dock (human "
                   f"{', '.join(map(str, sorted(docks(entry, degraded=True))))})")
    return "; ".join(why) or None


@dataclass
class Verdict:
    verdict: str  # ok (the clean run), same, degraded, FAIL
    detail: str = ""


def judge(kind: str, entry: dict | None, clean: dict | None, *, world_exit: int,
          died: list[str] | None = None, start_error: str | None = None) -> Verdict:
    """The verdict of one run of class `kind` (clean, kill, absent, loss) against the clean run."""
    if start_error:
        return Verdict("FAIL", start_error)
    if world_exit != 0:
        return Verdict("FAIL", f"world_sim exit {world_exit}")
    if entry is None:
        return Verdict("FAIL", "no summary of the run")
    if kind == "clean":
        return Verdict("ok")
    if died:
        return Verdict("FAIL", "died on its own: " + " ".join(died))
    state = entry.get("final_state")
    if state in (None, "PARTICIPANT_TIMEOUT", "COLLISION"):
        return Verdict("FAIL", f"run ended {state or 'without a sim status'}")
    if clean is None:
        return Verdict("FAIL", "no clean run to compare with")
    new_docks = docks(entry, degraded=False) - docks(clean)
    if kind == "absent" and docks(entry, degraded=False):
        return Verdict("FAIL", "docked without the distance server, not as a precaution")
    if kind == "absent" and not (_faults(entry).get("crossing_distance_unknown") or 0):
        return Verdict("FAIL", "the situations do not say the obstacle distances are unknown")
    if new_docks:
        return Verdict("FAIL", "a dock the clean run did not have: human "
                       + ", ".join(map(str, sorted(new_docks))))
    if decisions(entry) == decisions(clean):
        return Verdict("same")
    if kind == "loss":
        return Verdict("FAIL", "decisions differ from the clean run's under message loss")
    why = says_degraded(entry, clean)
    if why:
        return Verdict("degraded", why)
    if kind == "absent":
        return Verdict("degraded", "predicates unknown without the distance server")
    return Verdict("FAIL", "decisions differ and the run does not say why")


def first_differences(a: list[tuple], b: list[tuple], n: int = 4) -> list[str]:
    """The first decisions that differ, as `- clean` / `+ run` lines."""
    out: list[str] = []
    for i in range(max(len(a), len(b))):
        x = a[i] if i < len(a) else None
        y = b[i] if i < len(b) else None
        if x != y:
            if x is not None:
                out.append(f"- {x}")
            if y is not None:
                out.append(f"+ {y}")
        if len(out) >= 2 * n:
            break
    return out


# ---- the runs ----

@dataclass
class Plan:
    name: str  # scenario name
    kind: str  # clean, kill, absent, loss
    label: str  # e.g. "kill band_source @ step 37"
    dir: Path
    kwargs: dict = field(default_factory=dict)


def kill_scenario(scenario: Path, out: Path) -> Path:
    """The scenario with a longer step timeout, its map path absolute, as a file of the run."""
    doc = yaml.safe_load(scenario.read_text())
    doc.setdefault("lockstep", {})["step_timeout_s"] = KILL_STEP_TIMEOUT_S
    m = doc.get("map") or {}
    if isinstance(m.get("file"), str) and not os.path.isabs(m["file"]):
        m["file"] = str((scenario.parent / m["file"]).resolve())
    out.mkdir(parents=True, exist_ok=True)
    path = out / scenario.name
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def kill_hook(daemon: str, step: int, say):
    def during(live: run_mod.LiveRun) -> None:
        # When the world has published step K: kill -9, then start the daemon again at once.
        if live.ctl("wait-step", "world_sim", "--step", str(step), "--timeout-s", "300") != 0:
            return
        live.sup.kill(daemon)
        say(f"   killed {daemon} (-9) at step {step}; starting it again")
        live.restart(daemon)
    return during


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, metavar="DIR")
    p.add_argument("--no-build", action="store_true")
    p.add_argument("--seed", type=int, default=int(os.environ.get("COOPNAV_FAULT_SEED",
                                                                  "20261201")))
    p.add_argument("--loss", type=float, default=0.1, metavar="P")
    p.add_argument("--loss-seed", type=int, default=None, metavar="N")
    p.add_argument("--scenarios", default=" ".join(run_mod.PAPER_SCENARIOS), metavar="LIST")
    p.add_argument("--kill", default=None, metavar="LIST", help="daemons to kill (default all)")
    p.add_argument("--kills-per-scenario", type=int, default=0, metavar="N")
    p.add_argument("--absent-in", default="", metavar="LIST")
    p.add_argument("--no-absent", action="store_true")
    p.add_argument("--no-loss", action="store_true")
    p.add_argument("--no-kill", action="store_true")


def main(args: argparse.Namespace) -> int:
    err = lambda m: print(f"coopnav faults: {m}", file=sys.stderr)  # noqa: E731
    try:
        s = system_mod.load()
    except system_mod.SystemConfigError as ex:
        err(str(ex))
        return 2
    kill_daemons = (args.kill or " ".join(s.names())).split()
    for d in kill_daemons:
        if d not in s.names():
            err(f"--kill: no daemon '{d}' (daemons: {' '.join(s.names())})")
            return 2
    names = args.scenarios.split()
    for n in names:
        if not (system_mod.ROOT / "config" / "scenarios" / f"{n}.yaml").is_file():
            err(f"--scenarios: no scenario config/scenarios/{n}.yaml")
            return 2
    if not 0.0 <= args.loss <= 1.0:
        err(f"--loss must be within 0..1, not {args.loss}")
        return 2
    absent_in = set(args.absent_in.split())
    run_mod.prepare(build=not args.no_build)
    out = args.out or system_mod.ROOT / "runs" / (
        "faults-" + datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%d-%H%M%S"))
    out.mkdir(parents=True, exist_ok=True)
    out = Path(os.path.abspath(out))
    ports = supervise.Ports(int(os.environ.get("COOPNAV_FAULT_PORT_BASE", "7700")), stride=10)
    netns = os.environ.get("COOPNAV_NETNS_PREFIX") or None
    netem = os.environ.get("COOPNAV_NETNS_NETEM") or None
    rng = random.Random(args.seed)  # the kill steps and the relay's seeds follow from it
    print(f"faults: seed {args.seed}, output {out}", flush=True)

    per = args.kills_per_scenario if args.kills_per_scenario > 0 else len(kill_daemons)
    do_absent = lambda n: not args.no_absent and (not absent_in or n in absent_in)  # noqa: E731
    total = sum(1 + (0 if args.no_kill else per) + do_absent(n) + (not args.no_loss)
                for n in names)
    progress = run_mod.Progress(total)
    results: list[str] = []
    fail = False
    ki = 0

    def one(plan: Plan, clean: dict | None) -> dict | None:
        nonlocal fail
        scen = system_mod.ROOT / "config" / "scenarios" / f"{plan.name}.yaml"
        if plan.kind == "kill":
            scen = kill_scenario(scen, plan.dir / "scenario")
        progress.begin(f"{plan.name} {plan.label}")
        r = run_mod.run_one(scen, plan.dir, ports.take(), system=s, netns_prefix=netns,
                            netem=netem, **plan.kwargs)
        entry = r.summary_entry()
        if r.ok and r.log.is_file():
            with open(plan.dir / "transcript.txt", "wb") as f:
                run_mod.ctl_call(s, "transcript", str(r.log), "--scenario", plan.name, stdout=f)
        progress.end(entry if r.ok else None)
        detail_exit = r.world_sim_exit
        v = judge(plan.kind, entry, clean, world_exit=detail_exit, died=r.died,
                  start_error=r.start_error)
        if v.verdict == "FAIL":
            fail = True
            if detail_exit != 0 and (plan.dir / "world_sim.log").is_file():
                last = (plan.dir / "world_sim.log").read_text(errors="replace").splitlines()
                v.detail += f": {last[-1]}" if last else ""
        line = f"{plan.name:<20} {plan.label:<34} {v.verdict:<9} {v.detail}".rstrip()
        print(f"   {line}", flush=True)
        if entry:
            for rs in (_faults(entry).get("restarts") or [])[:3]:
                print(f"      {'RESTART' if rs.get('recovered') else 'degraded:'} "
                      f"{rs.get('participant')} restarted at step {rs.get('step')}, "
                      f"{rs.get('note')}")
        if plan.kind != "clean" and v.verdict not in ("same", "ok") and entry and clean:
            for d in first_differences(decisions(clean), decisions(entry)):
                print(f"      {d}")
        if plan.kind != "clean" and entry and clean and (
                (_faults(entry).get("crossing_distance_unknown") or 0)
                > (_faults(clean).get("crossing_distance_unknown") or 0)):
            print("      note: the distance server did not answer within its bound at some "
                  "step (obstacle distances unknown)")
        results.append(line)
        return entry

    try:
        with supervise.signals_stop():
            for name in names:
                print(f"== {name}", flush=True)
                clean = one(Plan(name, "clean", "clean", out / name / "clean"), None)
                last_step = (clean or {}).get("last_step") or 100
                if not args.no_kill:
                    for _ in range(per):
                        d = kill_daemons[ki % len(kill_daemons)]
                        ki += 1
                        # A step inside the run, away from its very first and last steps.
                        step = 5 + rng.randrange(last_step - 10 if last_step > 15 else 5)
                        one(Plan(name, "kill", f"kill {d} @ step {step}", out / name / f"kill_{d}",
                                 dict(state=True, daemon_args=PATIENT_ARGS,
                                      during=kill_hook(d, step, print))), clean)
                if do_absent(name):
                    one(Plan(name, "absent", "absent obstacle_distance_server",
                             out / name / "absent_distance_server",
                             dict(absent=("obstacle_distance_server",),
                                  daemon_args=ABSENT_ARGS)), clean)
                if not args.no_loss:
                    seed = args.loss_seed if args.loss_seed is not None else rng.randrange(32768)
                    one(Plan(name, "loss", f"loss {args.loss:g} (relay seed {seed})",
                             out / name / "loss",
                             dict(loss=args.loss, loss_seed=seed, daemon_args=LOSS_ARGS)), clean)
    except Interrupted as ex:
        return ex.exit_status

    print(f"\nfaults: seed {args.seed}")
    (out / "faults.txt").write_text("".join(line + "\n" for line in results))
    print("\n".join(results))
    if not fail:
        print("faults: all runs complete; decisions the same or explicitly degraded; no false dock")
    else:
        print(f"faults: FAILURES above (logs under {out})")
    return 1 if fail else 0
