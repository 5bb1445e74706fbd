"""The daemons across hosts (README "Network and hosts"), network namespaces for hosts.

Every process of a run (the five daemons, world_sim, the recorder) on a host of its own, one NIC
each (a veth) on a switch (a bridge in a namespace of its own; scripts/netns.sh), LCM multicast
routed on the NIC with ttl=1, as a robot's computers on one subnet would run them. Nothing of it
reaches this machine's own network namespace or its other LCM runs. Checks:
  1. single host vs. hosts: the scenarios run as `scripts/coopnav run` runs them (one host,
     ttl=0), then each process on its own host: the transcripts must be byte-identical;
  2. loss: each scenario again with every link lossy (default 5 % and 20 ms +- 5 ms delay per
     link, netem; where the kernel has no netem, a coopnav_lossy_relay on every host drops the
     same fraction of what goes out and of what comes in, without delay: the output says which);
     the decisions must be the clean run's (`scripts/coopnav faults`' loss verdict);
  3. a host drops off: in one scenario (narrow_minimal) the path assessor's cable is pulled at
     the switch once the world has passed step K, halfway between round 1 and round 2 of the
     single-host run (on a busy machine the pull lands some steps later). The world must end the
     run (PARTICIPANT_TIMEOUT, after the scenario's step_timeout_s, 20 s) with the path assessor
     the participant behind, rather than go on without it; the dialogue manager must have run
     steps without it (it acknowledged later steps than the path assessor did, and reported
     itself DEGRADED); and what the robot said and did until then must be the single-host run's;
  4. the recipe of README "Network and hosts": scripts/launch.sh on three hosts (the distance
     server and the band source on one, the assessors and the dialogue manager on another,
     world_sim on a third), the same scenario: its transcript must be the single-host one.
Every verdict is computed from the runs' summary.json (`coopnav_ctl summarize`: decisions, final
state, `faults.last_acked_step`, `faults.degraded_daemons`) and from the transcripts as files.
Needs root (network namespaces); where they cannot be made it prints "SKIP: <reason>" and exits
77. Namespaces are named cnmh<pid>-<host> and removed on any exit (and at the next start if a
run was killed before it could remove them). Writes everything under OUT (default
runs/multihost-<UTC>): single/, hosts/ (clean and loss runs), dropoff/, launch/, multihost.txt
(the verdicts and wall times).

  scripts/coopnav multihost [--out DIR] [--no-build] [--scenarios "open_minimal ..."]
                            [--loss-scenarios "narrow_minimal ..."] [--no-loss] [--loss P]
                            [--delay "20ms 5ms"] [--loss-seed N] [--dropoff-scenario NAME]
                            [--no-dropoff] [--no-launch] [--port-base N]
  (scripts/multihost.sh takes the same options.)
  --loss-scenarios: the loss pass on these only (default: every scenario of --scenarios).
  --port-base N: the single-host runs use ports N..N+3 of this machine (default 9100, or
  COOPNAV_MULTIHOST_PORT_BASE); the hosts' ports are their own.
Exit status: 0 every check passes; 1 a FAIL; 2 bad arguments; 77 no namespaces here.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import subprocess
import sys
import time
from pathlib import Path

from . import faults, run as run_mod, supervise, system as system_mod
from .faults import Verdict
from .supervise import Interrupted

DROPPED = "path_assessor"  # the host that drops off
WAITER = "dialogue_manager"  # the daemon that waits for its outputs and must go on without them
STEPS_PER_S = 10  # world_sim's steps (publish_hz)


# ---- verdicts (pure: tested in test/py/test_multihost.py) ----

def said(entry: dict) -> dict:
    """Per human id: what the robot said and did to them (faults.decisions' say, action and
    recorder tuples, in order), without the final CMs and the end of the run."""
    out: dict = {}
    for t in faults.decisions(entry):
        if t[0] in ("FINAL CM", "SIM"):
            continue
        out.setdefault(t[1], []).append(t)
    return out


def round_times(entry: dict) -> tuple[float | None, float | None]:
    """The times of the run's first round-1 and first round-2 words (any human)."""
    first: dict[int, float] = {}
    for h in entry.get("humans") or []:
        for e in h.get("transcript") or []:
            r, t = e.get("round"), e.get("t_s")
            if e.get("kind") == "say" and r in (1, 2) and isinstance(t, (int, float)):
                first[r] = min(first.get(r, t), t)
    return first.get(1), first.get(2)


def drop_step(ref: dict | None, default: int = 100) -> int:
    """K: the step halfway between round 1 and round 2 of the reference run (the path assessor
    is recording CA for round 2 then); `default` when the reference has not both rounds."""
    t1, t2 = round_times(ref or {})
    if t1 is None or t2 is None:
        return default
    return int((t1 + t2) / 2 * STEPS_PER_S)


def same_file(a: Path, b: Path) -> bool:
    try:
        return a.read_bytes() == b.read_bytes()
    except OSError:
        return False


def judge_same_transcript(a: Path, b: Path) -> Verdict:
    if not a.is_file() or not b.is_file():
        return Verdict("FAIL", "a transcript is missing")
    if same_file(a, b):
        return Verdict("same")
    return Verdict("FAIL", "the transcripts differ")


def judge_dropoff(entry: dict | None, ref: dict | None, *, dropped: str = DROPPED,
                  waiter: str = WAITER) -> Verdict:
    """The drop-off run against the single-host run of the same scenario."""
    if entry is None:
        return Verdict("FAIL", "no summary of the run")
    if ref is None:
        return Verdict("FAIL", "no single-host run to compare with")
    state = entry.get("final_state")
    if state != "PARTICIPANT_TIMEOUT":
        return Verdict("FAIL", f"the run did not end with a participant timeout: {state}")
    f = entry.get("faults") or {}
    last = f.get("last_acked_step") or {}
    if dropped not in last:
        return Verdict("FAIL", f"{dropped} acknowledged no step")
    cut = last[dropped]
    world = last.get("world_sim", entry.get("last_step"))
    if world is None or cut >= world or cut > min(last.values()):
        return Verdict("FAIL", f"{dropped} is not the participant the world waited for "
                       f"(last acknowledged steps: {last})")
    degraded = [d for d in f.get("degraded_daemons") or [] if d.get("name") == waiter]
    if last.get(waiter, -1) <= cut or not degraded:
        return Verdict("FAIL", f"{waiter} did not run without {dropped} (its last step "
                       f"{last.get(waiter)}, {dropped}'s {cut}; "
                       f"{'DEGRADED' if degraded else 'never DEGRADED'})")
    mine, theirs = said(entry), said(ref)
    for hid, entries in mine.items():
        if theirs.get(hid, [])[:len(entries)] != entries:
            ref_h = theirs.get(hid, [])
            k = next((i for i, (x, y) in enumerate(zip(ref_h, entries)) if x != y),
                     min(len(ref_h), len(entries)))
            got = entries[k] if k < len(entries) else None
            return Verdict("FAIL", f"decisions differ from the single-host run's: human {hid}: "
                           f"{got}")
    return Verdict("ok", f"{dropped} last acknowledged step {cut}, {waiter} went on to step "
                   f"{last[waiter]} ({degraded[0].get('detail')}); world stopped at step "
                   f"{entry.get('last_step')}: {entry.get('detail')}")


# ---- the hosts ----

def _netns_sh(*call: str) -> subprocess.CompletedProcess:
    """A function of scripts/netns.sh (the namespaces' own tool) with its arguments."""
    root = system_mod.ROOT
    return subprocess.run(["bash", "-c", f'source "{root}/scripts/lib.sh"; source '
                           f'"{root}/scripts/netns.sh"; "$@"', "netns", *call],
                          stdout=subprocess.PIPE, text=True)


def _on(prefix: str, host: str) -> list[str]:
    return ["ip", "netns", "exec", f"{prefix}-{host}"]


def _wall(r: run_mod.RunResult) -> str:
    try:
        t = json_timing(r.out_dir)
    except (OSError, ValueError, KeyError):
        return "?"
    return f"{t:.1f}"


def json_timing(out_dir: Path) -> float:
    """A run's wall time from its timing.json (coopnav_exp.timing)."""
    doc = json.loads((out_dir / "timing.json").read_text())
    return float(doc["total_s"])


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, metavar="DIR")
    p.add_argument("--no-build", action="store_true")
    p.add_argument("--scenarios", default=" ".join(run_mod.PAPER_SCENARIOS), metavar="LIST")
    p.add_argument("--loss-scenarios", default="", metavar="LIST")
    p.add_argument("--no-loss", action="store_true")
    p.add_argument("--loss", type=float, default=0.05, metavar="P")
    p.add_argument("--delay", default="20ms 5ms", metavar="'MEAN JITTER'")
    p.add_argument("--loss-seed", type=int, default=33, metavar="N")
    p.add_argument("--dropoff-scenario", default="narrow_minimal", metavar="NAME")
    p.add_argument("--no-dropoff", action="store_true")
    p.add_argument("--no-launch", action="store_true")
    p.add_argument("--port-base", type=int,
                   default=int(os.environ.get("COOPNAV_MULTIHOST_PORT_BASE", "9100")), metavar="N")


def main(args: argparse.Namespace) -> int:
    err = lambda m: print(f"multihost: {m}", file=sys.stderr)  # noqa: E731
    try:
        s = system_mod.load()
    except system_mod.SystemConfigError as ex:
        err(str(ex))
        return 2
    names = args.scenarios.split()
    loss_names = [] if args.no_loss else (args.loss_scenarios.split() or list(names))
    for n in names + loss_names + [args.dropoff_scenario]:
        if not (system_mod.ROOT / "config" / "scenarios" / f"{n}.yaml").is_file():
            err(f"no scenario config/scenarios/{n}.yaml")
            return 2
    prefix = f"cnmh{os.getpid()}"
    _netns_sh("coopnav_netns_reap_stale")
    check = _netns_sh("coopnav_netns_check", prefix)
    if check.returncode != 0:  # before building: a machine without namespaces skips at once
        print(f"SKIP: {check.stdout.strip()}")
        return 77
    run_mod.prepare(build=not args.no_build)
    out = args.out or system_mod.ROOT / "runs" / (
        "multihost-" + datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%d-%H%M%S"))
    out.mkdir(parents=True, exist_ok=True)
    out = Path(os.path.abspath(out))
    hosts = [*s.names(), "world_sim", "recorder"]
    print(f"multihost: output {out}; hosts are namespaces {prefix}-{{{','.join(hosts)}}}",
          flush=True)
    try:
        with supervise.signals_stop():
            try:
                return _checks(args, s, out, prefix, hosts, names, loss_names)
            finally:
                _netns_sh("coopnav_netns_down", prefix)
    except Interrupted as ex:
        return ex.exit_status


def _checks(args: argparse.Namespace, s: system_mod.System, out: Path, prefix: str,
            hosts: list[str], names: list[str], loss_names: list[str]) -> int:
    results: list[str] = []
    fail = False

    def note(line: str) -> None:
        results.append(line)
        print(line, flush=True)

    def row(scen: str, what: str, v: Verdict) -> None:
        nonlocal fail
        fail = fail or v.verdict == "FAIL"
        note(f"{scen:<20} {what:<28} {v.verdict:<9} {v.detail}".rstrip())

    def scenario(name: str) -> Path:
        return system_mod.ROOT / "config" / "scenarios" / f"{name}.yaml"

    def one(name: str, d: Path, port: int, **kw) -> run_mod.RunResult:
        r = run_mod.run_one(scenario(name), d, port, system=s, **kw)
        if r.log.is_file():
            with open(d / "transcript.txt", "wb") as f:
                run_mod.ctl_call(s, "transcript", str(r.log), "--scenario", name, stdout=f)
        return r

    # 1a. One host, as `scripts/coopnav run` runs each scenario.
    print("== single host", flush=True)
    single: dict[str, run_mod.RunResult] = {}
    t0 = time.monotonic()
    for i, name in enumerate(dict.fromkeys(names + [args.dropoff_scenario])):
        if name not in names and args.no_dropoff and args.no_launch:
            continue
        r = one(name, out / "single" / name, args.port_base + i)
        single[name] = r
        if not r.ok or r.world_sim_exit != 0:
            print(f"multihost: FAIL: the single-host run of {name} failed (see {r.out_dir})")
            return 1
    note(f"single host: {time.monotonic() - t0:.0f} s for {len(single)} scenarios")

    # 1b + 2. Every process on its own host: clean runs, then loss runs (faults' loss verdict).
    if _netns_sh("coopnav_netns_up", prefix, *hosts).returncode != 0:
        print("multihost: FAIL: the hosts could not be made")
        return 1
    netem = None
    if loss_names:
        probe = subprocess.run(_on(prefix, "world_sim") + [
            "tc", "qdisc", "add", "dev", "eth0", "root", "netem", "loss", "5%", "delay",
            "20ms", "5ms"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if probe.returncode == 0:
            subprocess.call(_on(prefix, "world_sim") + ["tc", "qdisc", "del", "dev", "eth0",
                                                         "root"])
            netem = f"delay {args.delay}"
            note(f"loss pass: netem on both ends of every link but the recorder's: loss "
                 f"{args.loss:g}, delay {args.delay}")
        else:
            note(f"loss pass: coopnav_lossy_relay on every host but the recorder's, loss "
                 f"{args.loss:g} on the way out and on the way in, no delay (the kernel refused "
                 f"netem: {' '.join(probe.stdout.split())})")
    print("== each process on its own host (clean runs, loss runs)", flush=True)
    ports = supervise.Ports(args.port_base + 10, stride=10)
    hosts_clean: dict[str, dict | None] = {}
    verdicts: dict[tuple[str, str], tuple[Verdict, run_mod.RunResult | None]] = {}
    t0 = time.monotonic()
    for name in names:
        r = one(name, out / "hosts" / name / "clean", ports.take(), netns_prefix=prefix)
        hosts_clean[name] = r.summary_entry()
        v = faults.judge("clean", hosts_clean[name], None, world_exit=r.world_sim_exit,
                         died=r.died, start_error=r.start_error)
        verdicts[(name, "clean")] = (v, r)
        if name in loss_names:
            rl = one(name, out / "hosts" / name / "loss", ports.take(), netns_prefix=prefix,
                     netem=netem, loss=args.loss, loss_seed=args.loss_seed,
                     daemon_args=faults.LOSS_ARGS)
            vl = faults.judge("loss", rl.summary_entry(), hosts_clean[name],
                              world_exit=rl.world_sim_exit, died=rl.died,
                              start_error=rl.start_error)
            verdicts[(name, "loss")] = (vl, rl)
    note(f"hosts: {time.monotonic() - t0:.0f} s for {len(names)} clean runs and "
         f"{len(loss_names)} loss runs")

    print("== verdicts", flush=True)
    for name in names:
        vc, rc = verdicts[(name, "clean")]
        v = vc if vc.verdict == "FAIL" else judge_same_transcript(
            single[name].out_dir / "transcript.txt", rc.out_dir / "transcript.txt")
        if v.verdict == "same":
            v.detail = f"wall {_wall(rc)} s (one host {_wall(single[name])} s)"
        row(name, "hosts vs one host", v)
        if (name, "loss") in verdicts:
            vl, rl = verdicts[(name, "loss")]
            if vl.verdict == "same":
                vl.detail = f"wall {_wall(rl)} s"
            row(name, f"hosts, loss {args.loss:g} ({'netem' if netem else 'relay'})", vl)
            if vl.verdict == "FAIL" and rl and hosts_clean[name] and rl.summary_entry():
                for d in faults.first_differences(faults.decisions(hosts_clean[name]),
                                                  faults.decisions(rl.summary_entry())):
                    print(f"      {d}")

    ref_name = args.dropoff_scenario
    ref = single.get(ref_name)
    ref_entry = ref.summary_entry() if ref else None

    # 3. A host drops off: the path assessor's cable pulled between round 1 and round 2.
    if not args.no_dropoff:
        print(f"== a host drops off ({ref_name}: the path assessor's cable pulled)", flush=True)
        k = drop_step(ref_entry)

        def pull(live: run_mod.LiveRun) -> None:
            # Once the world has acknowledged step K, the path assessor's host leaves the network.
            if live.ctl("wait-step", "world_sim", "--step", str(k), "--timeout-s", "300") != 0:
                return
            _netns_sh("coopnav_netns_cable", prefix, DROPPED, "down")
            print(f"   cable of the path assessor's host pulled after step {k}", flush=True)

        t0 = time.monotonic()
        try:
            r = one(ref_name, out / "dropoff", args.port_base + 90, netns_prefix=prefix,
                    during=pull)
        finally:
            _netns_sh("coopnav_netns_cable", prefix, DROPPED, "up")
        v = judge_dropoff(r.summary_entry(), ref_entry)
        if v.verdict == "ok":
            v.detail = f"world_sim exit {r.world_sim_exit} after {time.monotonic() - t0:.0f} s; " \
                       + v.detail
        row(ref_name, f"path_assessor drops off @ {k}", v)

    # 4. The recipe (README "Network and hosts"): scripts/launch.sh on three hosts.
    if not args.no_launch:
        print(f"== the recipe: scripts/launch.sh on three hosts ({ref_name})", flush=True)
        row(ref_name, "launch.sh on three hosts",
            _launch_recipe(s, out / "launch", prefix, ref_name, scenario(ref_name),
                           args.port_base + 80, ref.out_dir / "transcript.txt" if ref else None))

    print()
    (out / "multihost.txt").write_text("".join(line + "\n" for line in results))
    print(f"multihost: {'all checks pass' if not fail else 'FAILURES above'} (output {out})")
    return 1 if fail else 0


def _launch_recipe(s: system_mod.System, d: Path, prefix: str, name: str, scen: Path, port: int,
                   ref_transcript: Path | None) -> Verdict:
    """The distance server and the band source on one host, the assessors and the dialogue
    manager on another, world_sim on a third (scripts/launch.sh each); the recorder on its own."""
    url = f"udpm://239.255.76.67:{port}?ttl=1&recv_buf_size=4194304"
    launch = ["bash", str(system_mod.ROOT / "scripts" / "launch.sh"), "--url", url]
    log = d / f"{name}.lcm"
    ctl = str(s.tool("ctl"))
    t0 = time.monotonic()
    rc = 0
    with supervise.Supervisor() as sup:
        sup.start("recorder", _on(prefix, "recorder") + [
            str(s.tool("recorder")), "-f", "-c", s.recorder_channels, "--lcm-url", url, str(log)],
            d / "record.log", append=False)
        sup.start("host_a", _on(prefix, "band_source") + launch + [
            "--map", str(scen), "--log-dir", str(d / "host_a"), "obstacle_distance_server",
            "band_source"], d / "host_a.out", append=False)
        sup.start("host_b", _on(prefix, "dialogue_manager") + launch + [
            "--log-dir", str(d / "host_b"), "situation_assessor", "path_assessor",
            "dialogue_manager"], d / "host_b.out", append=False)
        with open(d / "wait-ready.log", "wb") as f:
            rc = subprocess.call(_on(prefix, "recorder") + [
                ctl, "--lcm-url", url, "wait-ready", *s.names(), "--timeout-s", "60"],
                stdout=f, stderr=subprocess.STDOUT)
        if rc == 0:
            env = dict(os.environ, COOPNAV_DAEMON_ARGS_world_sim=f"--set scenario={scen}")
            with open(d / "host_c.out", "wb") as f:
                rc = subprocess.call(_on(prefix, "world_sim") + launch + [
                    "--log-dir", str(d / "host_c"), "world_sim"], stdout=f,
                    stderr=subprocess.STDOUT, env=env)
            _wait_recorded(log)
        sup.stop_all()  # SIGTERM: each launcher stops its daemons
    with open(d / "transcript.txt", "wb") as f:
        run_mod.ctl_call(s, "transcript", str(log), "--scenario", name, stdout=f)
    same = ref_transcript is not None and same_file(ref_transcript, d / "transcript.txt")
    if rc == 0 and same:
        return Verdict("same", f"wall {time.monotonic() - t0:.0f} s")
    return Verdict("FAIL", f"launch.sh exit {rc} (see {d}); the transcript is "
                   f"{'' if same else 'not '}the single-host one")


def _wait_recorded(log: Path) -> None:
    """The last messages reach the recorder: until the file stopped growing for 0.3 s (at most
    ~5 s), as scripts/lib.sh's coopnav_wait_recorded."""
    size = -1
    for _ in range(16):
        time.sleep(0.3)
        now = log.stat().st_size if log.exists() else 0
        if now == size:
            return
        size = now
