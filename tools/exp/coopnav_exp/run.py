"""Runs the paper's experiment (§III): each scenario with every daemon as its own process.

For each scenario: the daemons of config/system.yaml on a host-local LCM port of the run's own,
world_sim in lockstep, an LCM log; then the transcript (what the robot said and did, when and
why) and, over all scenarios, the CM table beside the paper's Table I. Writes runs/<timestamp>/
and runs/latest (or --out DIR).

  scripts/coopnav run [--out DIR] [--no-build] [--profile paper|calibrated|forecast|make_time] [--speech]
                      [scenario.yaml ...]
  (scripts/run.sh takes the same options.) Default scenarios:
  config/scenarios/{open,narrow}_{facilitating,minimal}.yaml. --profile: the path assessment
  profile (config/system.yaml's profiles), default paper. --speech: espeak-ng says each utterance
  into DIR/<scenario>/speech/*.wav, and the dialogue manager plans with the durations it
  measures.
Environment: COOPNAV_RUN_PORT_BASE (7670: the first scenario's udpm port, one more per
scenario); COOPNAV_DAEMON_ARGS_<daemon or world_sim> (extra arguments of that process, split
at spaces, e.g. "--set k=v"); COOPNAV_BUILD_DIR (build/).
Exit status: 0 every run reached every goal without contact; 1 a run failed (no log, a daemon
died at start); 2 bad arguments; 3 a run ended in a contact, a standstill or the time limit
(each reason on stderr, from its summary.json): a safe run that does not progress fails too.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Mapping, Sequence

from . import supervise, system as system_mod, timing
from .supervise import Interrupted, StartError, Supervisor

MCAST = "239.255.76.67"
PAPER_SCENARIOS = ("open_facilitating", "open_minimal", "narrow_facilitating", "narrow_minimal")


def lcm_url(port: int, ttl: int = 0) -> str:
    return f"udpm://{MCAST}:{port}?ttl={ttl}&recv_buf_size=4194304"


@dataclass
class RunResult:
    """What one run left: world_sim's exit status and the paths of its files."""
    world_sim_exit: int  # 124: stopped after timeout_s; 1 with start_error: never started
    out_dir: Path
    log: Path  # the .lcm (may be missing when the run failed at start)
    summary: Path | None  # summary.json (coopnav_ctl summarize), None if there is none
    name: str = ""
    metrics: Path | None = None  # metrics.json (coopnav_ctl metrics; metrics.csv beside it)
    died: list[str] = field(default_factory=list)  # daemons not running when world_sim ended
    start_error: str | None = None

    @property
    def ok(self) -> bool:
        return self.world_sim_exit == 0 and self.start_error is None

    def summary_entry(self) -> dict | None:
        """The run's scenario entry of summary.json, or None."""
        return read_summary_entry(self.summary) if self.summary else None


class LiveRun:
    """What a hook sees of a run while world_sim runs (`during`) and after it ended (`after`)."""

    def __init__(self, system: system_mod.System, sup: Supervisor, out_dir: Path,
                 scenario: Path, name: str, url: str, urls: Mapping[str, str],
                 commands: Mapping[str, list[str]], env: Mapping[str, str],
                 on_host: Callable[[str], list[str]]):
        self.system, self.sup, self.out_dir, self.scenario, self.name = (
            system, sup, out_dir, scenario, name)
        self.url, self.urls, self.commands, self.env = url, urls, commands, env
        self.on_host = on_host

    def pid(self, daemon: str) -> int:
        return self.sup.procs[daemon].pid

    def restart(self, daemon: str) -> None:
        """Starts `daemon` again with the same command line (its log appended to)."""
        self.sup.start(daemon, self.on_host(daemon) + self.commands[daemon],
                       self.out_dir / f"{daemon}.log", env=self.env)

    def ctl(self, *args: str, timeout_s: float | None = None) -> int:
        """Runs coopnav_ctl on the scripts' host and bus; its exit status."""
        cmd = self.on_host("recorder") + [str(self.system.tool("ctl")), *args]
        try:
            return subprocess.call(cmd, env=dict(self.env), stdout=subprocess.DEVNULL,
                                   stderr=subprocess.DEVNULL, timeout=timeout_s,
                                   preexec_fn=supervise._die_with_parent)
        except subprocess.TimeoutExpired:
            return 124


Hook = Callable[[LiveRun], None]


def read_summary_entry(path: Path) -> dict | None:
    try:
        return json.loads(Path(path).read_text())["scenarios"][0]
    except (OSError, ValueError, KeyError, IndexError, TypeError):
        return None


def scenario_name(scenario: Path) -> str:
    return Path(scenario).name.removesuffix(".yaml")


def _netns(prefix: str | None, host: str) -> list[str]:
    return ["ip", "netns", "exec", f"{prefix}-{host}"] if prefix else []


def _netem(prefix: str, *args: str) -> int:
    """coopnav_netns_netem of scripts/netns.sh (the namespaces' own tool)."""
    root = system_mod.ROOT
    return subprocess.call(["bash", "-c", f'source "{root}/scripts/lib.sh"; source '
                            f'"{root}/scripts/netns.sh"; coopnav_netns_netem "$@"', "netem",
                            prefix, *args])


def run_one(scenario: Path, out_dir: Path, port: int, *, profile: str = "paper",
            daemon_args: Mapping[str, Sequence[str]] | None = None, absent: Sequence[str] = (),
            speech: bool = False, timeout_s: float = 900, state: bool = False,
            loss: float | None = None, loss_seed: int = 1, netns_prefix: str | None = None,
            netem: str | None = None, during: Hook | None = None, after: Hook | None = None,
            summarize: bool = True, system: system_mod.System | None = None) -> RunResult:
    """One run of `scenario` with every daemon as its own process, world_sim in lockstep.

    Starts the recorder (out_dir/<name>.lcm), a waiter that listens for the daemons' status
    messages, the daemons of config/system.yaml in order (less `absent`), waits until each said it
    is ready (its first status message; one that dies at start is reported at once) and the
    recorder listens, runs world_sim and stops everything once it exited (the recorder records
    what is still on its way before it closes the log: world_sim ends after every participant
    acknowledged its last step, so nothing of the run comes later). Every process logs to
    out_dir/<process>.log (appended to when a daemon is started again). Then `coopnav_ctl
    summarize` writes out_dir/summary.json (`summarize`). Where the wall time went:
    out_dir/timing.json (coopnav_exp.timing).

    port: the run's udpm port; with `loss` it also takes port + 1 and on (one per process).
    daemon_args: extra arguments per daemon or world_sim, after the system's own.
    state: every journaling daemon gets --state-dir out_dir/state (its restart journal).
    loss: each process on a port of its own, joined by coopnav_lossy_relay dropping that fraction
      of every forwarded message (seed loss_seed); the recorder and the hooks hear everything.
    netns_prefix: every process on a host of its own, the network namespace P-<name> (P-recorder:
      the recorder and coopnav_ctl), made by scripts/netns.sh; multicast then has ttl=1. With
      loss, each host gets its own relay between its process and the network, or with `netem`
      (netem's other arguments, e.g. "delay 20ms 5ms") the kernel drops on every link but the
      recorder's.
    during: called while world_sim runs (the world in the background); after: once it ended,
      before the daemons are stopped.
    timeout_s: world_sim's wall-time bound; past it the run is stopped (world_sim_exit 124).
    """
    s = system or system_mod.load()
    scenario = Path(os.path.abspath(scenario))
    out_dir = Path(os.path.abspath(out_dir))
    name = scenario_name(scenario)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "scenario.path").write_text(f"{scenario}\n")  # replay.sh finds the map by it
    log = out_dir / f"{name}.lcm"
    summary_path = out_dir / "summary.json"
    for n in absent:
        s.daemon(n)  # a name the system does not know is an error, not a silent no-op
    extra = {k: list(v) for k, v in (daemon_args or {}).items()}
    if speech:
        extra.setdefault("dialogue_manager", [])
        extra["dialogue_manager"] += ["--set", "speech.enabled=true",
                                      "--set", f"speech.wav_dir={out_dir / 'speech'}"]
    url = lcm_url(port, ttl=1 if netns_prefix else 0)
    env = dict(os.environ, LCM_DEFAULT_URL=url)
    procs = s.names() + [s.world.name]
    urls = {p: url for p in procs}
    sup = Supervisor(grace_s=s.timing.stop_grace_s)
    netem_on = False
    on_host = (lambda host: _netns(netns_prefix, host))
    relay = str(s.tool("lossy_relay"))
    result = RunResult(world_sim_exit=1, out_dir=out_dir, log=log, summary=None, name=name)
    tl = timing.Timeline()
    try:
        with sup:
            if loss is not None and netns_prefix:
                if netem:
                    # The kernel drops and delays on every link; the recorder's link is spared,
                    # as the relay spares the logger (a log that lacks a message is a wrong
                    # transcript, not a lossy run).
                    if _netem(netns_prefix, "on", f"loss {100 * loss:g}% {netem}", "recorder"):
                        raise StartError(f"netem refused on {netns_prefix}-*")
                    netem_on = True
                else:
                    # On each host a relay between its process (a host-local port: ttl=0 stays in
                    # the namespace) and the network drops that fraction of what goes out and of
                    # what comes in. Seeds differ per host.
                    priv = lcm_url(port + 1)
                    for i, p in enumerate(procs):
                        urls[p] = priv
                        sup.start(f"relay_{p}", on_host(p) + [
                            relay, "--endpoint", priv, "--endpoint", url, "--loss", f"{loss:g}",
                            "--seed", str(loss_seed + i)], out_dir / f"relay_{p}.log",
                            append=False, env=env)
            elif loss is not None:
                # Every process on a port of its own; the relay joins them (lossless towards the
                # recorder and the hooks, which stay on the shared URL).
                eps: list[str] = []
                for i, p in enumerate(procs):
                    urls[p] = lcm_url(port + 1 + i)
                    eps += ["--endpoint", urls[p]]
                sup.start("relay", [relay, *eps, "--lossless", url, "--loss", f"{loss:g}",
                                    "--seed", str(loss_seed)], out_dir / "relay.log",
                          append=False, env=env)
            sup.start("recorder", on_host("recorder") + [
                str(s.tool("recorder")), "-f", "-c", s.recorder_channels, "--lcm-url", url,
                str(log)], out_dir / "record.log", append=False, env=env)
            state_dir = out_dir / "state" if state else None
            commands = {
                p: s.command(p, scenario=scenario, profile=profile, state_dir=state_dir,
                             extra=extra.get(p, ()), lcm_url=urls[p])
                for p in procs}
            started = [d for d in s.names() if d not in absent]
            live = LiveRun(s, sup, out_dir, scenario, name, url, urls, commands, env, on_host)
            waiter = None
            try:
                # The waiter listens before the daemons start: it hears each one's first status.
                waiter = sup.start_waiter(on_host("recorder") + [
                    str(s.tool("ctl")), "wait-ready", *started, "--timeout-s",
                    f"{s.timing.ready_timeout_s:g}", "--announce"],
                    timeout_s=s.timing.ready_timeout_s, env=env) if started else None
                for d in started:
                    tl.spawned[d] = time.time()
                    sup.start(d, on_host(d) + commands[d], out_dir / f"{d}.log", env=env)
                tl.mark("spawned")
                if waiter is not None:
                    sup.wait_ready(waiter, started)
                tl.mark("ready")
                # The recorder subscribes before the first step (it said so, or never will).
                if not supervise.wait_for_line(out_dir / "record.log", "coopnav_record: recording",
                                               s.timing.ready_timeout_s):
                    raise StartError(f"the recorder is not recording (see {out_dir}/record.log)")
                tl.mark("recorder_ready")
            except StartError as ex:
                result.start_error = f"daemons did not come up for {name}: {ex}"
                print(f"coopnav: {ex}\ncoopnav: daemons did not come up for {name}; see "
                      f"{out_dir}/*.log", file=sys.stderr, flush=True)
                return result
            finally:
                if waiter is not None and waiter.poll() is None:
                    waiter.kill()
                    waiter.wait()
            world = sup.start(s.world.name, on_host(s.world.name) + commands[s.world.name],
                              out_dir / f"{s.world.name}.log", append=False, env=env)
            t0 = time.monotonic()
            if during:
                try:
                    during(live)
                except Interrupted:
                    raise
                except Exception as ex:  # a hook's failure is said, the run goes on
                    print(f"coopnav: {name}: hook failed: {ex!r}", file=sys.stderr)
            try:
                rc = world.popen.wait(timeout=max(0.0, timeout_s - (time.monotonic() - t0)))
            except subprocess.TimeoutExpired:
                sup.stop([world])
                rc = 124
                with open(world.log, "a") as f:
                    f.write(f"coopnav: world_sim stopped after {timeout_s:g} s of wall time\n")
            result.world_sim_exit = rc
            tl.mark("world_exited")
            result.died = [d for d in started if not sup.procs[d].alive()]
            if after:
                after(live)
            tl.mark("after")
        tl.mark("stopped")
    finally:
        if netem_on:
            _netem(netns_prefix, "off")  # type: ignore[arg-type]
    if summarize and log.is_file():
        rc = supervise.call_logged([str(s.tool("ctl")), "summarize", str(log), "--scenario", name,
                                    "--out", str(summary_path)], out_dir / "summarize.log")
        if rc == 0 and summary_path.is_file():
            result.summary = summary_path
        result.metrics = write_metrics(s, log, scenario, out_dir)
        tl.mark("summarized")
    tl.write(out_dir, s.world.name)
    return result


def write_metrics(s: system_mod.System, log: Path, scenario: Path, out_dir: Path) -> Path | None:
    """The field's metrics of the run (docs/metrics.md), scored from its log with the scenario as
    the map: out_dir/metrics.json and metrics.csv (`coopnav_ctl metrics`, its output in
    metrics.log). Returns the JSON's path, None when the log could not be scored."""
    json_path, csv_path = out_dir / "metrics.json", out_dir / "metrics.csv"
    rc = supervise.call_logged([str(s.tool("ctl")), "metrics", str(log), "--map", str(scenario),
                                "--json", str(json_path), "--csv", str(csv_path)],
                               out_dir / "metrics.log")
    return json_path if rc == 0 and json_path.is_file() else None


def outcome_failure(entry: dict | None) -> str | None:
    """Why a run that ran to its end counts as failed: a contact (whoever caused it), a
    standstill or the time limit; None for a run that reached every goal without contact."""
    if entry is None:
        return "no readable summary"
    state, contact = entry.get("final_state"), entry.get("contact")
    reasons = []
    if entry.get("collision") or contact:
        c = contact if isinstance(contact, dict) else {}
        fault = "robot at fault" if c.get("robot_at_fault") else "robot not at fault"
        reasons.append(f"contact with human {c.get('human_id', '?')} at t = {c.get('t_s')} s "
                       f"({fault})")
    if state in ("STANDSTILL", "TIME_LIMIT"):
        reasons.append(f"{state} at t = {entry.get('sim_time_s')} s")
    elif state != "GOAL_REACHED" and not reasons:
        reasons.append(f"final state {state}")
    if not reasons:
        return None
    return "; ".join(reasons) + (f": {entry['detail']}" if entry.get("detail") else "")


def daemon_args_from_env(s: system_mod.System,
                         environ: Mapping[str, str] = os.environ) -> dict[str, list[str]]:
    """COOPNAV_DAEMON_ARGS_<name> of every daemon and the world, split at white space."""
    out = {}
    for n in s.names() + [s.world.name]:
        v = environ.get(f"COOPNAV_DAEMON_ARGS_{n}", "")
        if v.split():
            out[n] = v.split()
    return out


def prepare(build: bool) -> None:
    """What the scripts did before a run: Debian packages and the build (unless --no-build), a
    multicast route and LCM's receive buffers (scripts/lib.sh)."""
    steps = ("coopnav_install_deps; coopnav_build; " if build else "") + "coopnav_ensure_multicast"
    rc = subprocess.call(["bash", "-c", f'source "{system_mod.ROOT}/scripts/lib.sh"; {steps}'])
    if rc != 0:
        raise SystemExit(rc)


class Progress:
    """One line per finished run: the simulated time it covered, its outcome, its wall time and
    the job's ETA (mean wall time so far times the runs left). On a terminal a line ticks in
    place while a run goes on; piped, only the finished lines are printed."""

    def __init__(self, total: int, stream=None):
        self.total, self.done, self.wall_s = total, 0, 0.0
        self.stream = stream or sys.stdout
        self._stop: threading.Event | None = None
        self._thread: threading.Thread | None = None
        self.label, self.t0 = "", 0.0

    def eta(self) -> str:
        left = self.total - self.done
        if self.done == 0:
            return "ETA unknown"
        return "done" if left == 0 else f"ETA {self.wall_s / self.done * left:.0f} s"

    def begin(self, label: str) -> None:
        self.label, self.t0 = label, time.monotonic()
        if not self.stream.isatty():
            return
        n, eta, stop = self.done + 1, self.eta(), threading.Event()

        def tick() -> None:
            while not stop.wait(1.0):
                self.stream.write(f"\r\033[K[{n}/{self.total}] {label}: running, "
                                  f"{time.monotonic() - self.t0:.0f} s wall; {eta}")
                self.stream.flush()

        self._stop, self._thread = stop, threading.Thread(target=tick, daemon=True)
        self._thread.start()

    def end(self, entry: dict | None) -> None:
        if self._stop and self._thread:
            self._stop.set()
            self._thread.join()
            self._stop = self._thread = None
            self.stream.write("\r\033[K")
        wall = time.monotonic() - self.t0
        self.done += 1
        self.wall_s += wall
        sim = entry.get("sim_time_s") if entry else None
        outcome = (entry.get("final_state") if entry else None) or "no end"
        sim_text = f"{sim:.2f}" if isinstance(sim, (int, float)) else "?"
        self.stream.write(f"[{self.done}/{self.total}] {self.label}: {sim_text} s simulated "
                          f"({outcome}) in {wall:.1f} s wall; {self.eta()}\n")
        self.stream.flush()


def ctl_call(s: system_mod.System, *args: str, stdout=None) -> int:
    return subprocess.call([str(s.tool("ctl")), *args], stdout=stdout)


# ---- the command ----

def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, metavar="DIR",
                   help="output folder (default runs/<UTC timestamp>, linked as runs/latest)")
    p.add_argument("--no-build", action="store_true", help="run the build as it is")
    p.add_argument("--profile", default="paper", metavar="PROFILE",
                   help="a profile of config/system.yaml: paper, calibrated, forecast or make_time "
                        "(default paper)")
    p.add_argument("--speech", action="store_true",
                   help="espeak-ng says each utterance into DIR/<scenario>/speech/*.wav")
    p.add_argument("scenarios", nargs="*", type=Path, metavar="scenario.yaml")


def main(args: argparse.Namespace) -> int:
    err = lambda m: print(f"coopnav run: {m}", file=sys.stderr)  # noqa: E731
    try:
        s = system_mod.load()
    except system_mod.SystemConfigError as ex:
        err(str(ex))
        return 2
    scenarios = list(args.scenarios) or [
        system_mod.ROOT / "config" / "scenarios" / f"{n}.yaml" for n in PAPER_SCENARIOS]
    for sc in scenarios:
        if not sc.is_file():
            err(f"no scenario file '{sc}'")
            return 2
    if args.profile not in s.profiles:
        err(f"--profile must be {system_mod.one_of(s.profiles)}, not '{args.profile}'")
        return 2
    prepare(build=not args.no_build)
    if args.out is None:
        stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%d-%H%M%S")
        out = system_mod.ROOT / "runs" / stamp
        out.mkdir(parents=True, exist_ok=True)
        latest = system_mod.ROOT / "runs" / "latest"
        tmp = latest.with_name(".latest.tmp")
        tmp.unlink(missing_ok=True)
        tmp.symlink_to(stamp)
        tmp.replace(latest)
    else:
        out = args.out
        out.mkdir(parents=True, exist_ok=True)
    out = Path(os.path.abspath(out))
    port = int(os.environ.get("COOPNAV_RUN_PORT_BASE", "7670"))
    env_args = daemon_args_from_env(s)
    ctl = str(s.tool("ctl"))
    summaries: list[Path] = []
    ended_badly: list[str] = []
    failed = 0
    progress = Progress(len(scenarios))
    try:
        with supervise.signals_stop():
            for scenario in scenarios:
                scenario = Path(os.path.abspath(scenario))
                name = scenario_name(scenario)
                d = out / name
                print(f"== {name}  ({scenario})", flush=True)
                progress.begin(name)
                r = run_one(scenario, d, port, profile=args.profile, daemon_args=env_args,
                            speech=args.speech, system=s)
                port += 1
                if not r.ok:
                    progress.end(None)
                    err(f"the run failed (exit {r.world_sim_exit}) for {name}; see {d}/*.log")
                    tail = (d / "world_sim.log")
                    if tail.is_file():
                        sys.stderr.write("".join(
                            line + "\n" for line in tail.read_text(errors="replace")
                            .splitlines()[-5:]))
                    failed = 1
                    continue
                transcript = d / "transcript.txt"
                with open(transcript, "wb") as f:
                    ctl_call(s, "transcript", str(r.log), "--scenario", name, stdout=f)
                progress.end(r.summary_entry())
                sys.stdout.write(transcript.read_text())
                sys.stdout.flush()
                if r.summary is None:  # summarize failed in run_one: say why, here
                    ctl_call(s, "summarize", str(r.log), "--scenario", name, "--out",
                             str(d / "summary.json"))
                print(f"   view this run: {s.tool('viewer')} --log {r.log}  then open "
                      "http://127.0.0.1:8088/", flush=True)
                summaries.append(d / "summary.json")
                reason = outcome_failure(read_summary_entry(d / "summary.json"))
                if reason:
                    err(f"{name}: {reason}")
                    ended_badly.append(f"{name}: {reason}")
                print(flush=True)
    except Interrupted as ex:
        return ex.exit_status
    if summaries:
        ctl_call(s, "merge-summaries", str(out / "summary.json"), *map(str, summaries))
        table = subprocess.run([ctl, "cm-table", str(out / "summary.json")], stdout=subprocess.PIPE)
        (out / "cm_table.txt").write_bytes(table.stdout)
        sys.stdout.buffer.write(table.stdout)
        sys.stdout.flush()
        # COOPNAV_FIGURES=0: no figures (matplotlib, ~1.5 s of CPU a scenario), e.g. in tests.
        figures = os.environ.get("COOPNAV_FIGURES", "1") != "0"
        if figures:
            subprocess.run([sys.executable, str(system_mod.ROOT / "scripts" / "coopnav"), "figures",
                            *(str(p.parent) for p in summaries)], stdout=subprocess.DEVNULL,
                           check=False)
        print(f"run directory: {out} (logs, transcripts, summary.json"
              + (", trace.json, figures *.png *.svg)" if figures else ")"))
    if failed == 0 and ended_badly:
        for line in ended_badly:
            err(line)
        failed = 3
    return failed



# ---- run-one: one run for the bash scripts that remain (scripts/scenario.sh) ----

def run_one_main(args: argparse.Namespace) -> int:
    """One run (run_one) for a script: exits with world_sim's status (1: never started).

    scripts/scenario.sh's coopnav_run_scenario calls it; the knobs come from the environment
    that function documents (COOPNAV_ABSENT, COOPNAV_STATE, COOPNAV_LOSS, COOPNAV_LOSS_SEED,
    COOPNAV_PROFILE, COOPNAV_NETNS_PREFIX, COOPNAV_NETNS_NETEM, COOPNAV_DAEMON_ARGS_<name>).
    --world-started FILE: written once world_sim runs (a script's hook starts then), holding
    the run's LCM URL."""
    try:
        s = system_mod.load()
        env = os.environ
        loss = env.get("COOPNAV_LOSS") or None
        started = args.world_started

        def during(live: LiveRun) -> None:
            if started:  # the run's bus: what a script's hook listens to
                started.write_text(live.url + "\n")

        with supervise.signals_stop():
            r = run_one(args.scenario, args.dir, args.port,
                        profile=env.get("COOPNAV_PROFILE") or "paper",
                        daemon_args=daemon_args_from_env(s),
                        absent=tuple(env.get("COOPNAV_ABSENT", "").split()),
                        state=env.get("COOPNAV_STATE", "0") == "1",
                        loss=float(loss) if loss else None,
                        loss_seed=int(env.get("COOPNAV_LOSS_SEED") or 1),
                        netns_prefix=env.get("COOPNAV_NETNS_PREFIX") or None,
                        netem=env.get("COOPNAV_NETNS_NETEM") or None,
                        timeout_s=args.timeout_s, during=during, summarize=args.summarize,
                        system=s)
    except (system_mod.SystemConfigError, KeyError, ValueError) as ex:
        print(f"coopnav run-one: {ex}", file=sys.stderr)
        return 2
    except Interrupted as ex:
        return ex.exit_status
    return r.world_sim_exit


def _run_one_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("scenario", type=Path)
    p.add_argument("dir", type=Path)
    p.add_argument("port", type=int)
    p.add_argument("--world-started", type=Path, default=None, metavar="FILE")
    p.add_argument("--timeout-s", type=float, default=900.0)
    p.add_argument("--summarize", action="store_true", help="write DIR/summary.json")


run_one_main.add_arguments = _run_one_arguments  # type: ignore[attr-defined]


# ---- outcome: a run's verdict for a script (scripts/deb_check.sh) ----

def outcome_main(args: argparse.Namespace) -> int:
    """The outcome of recorded runs from their summary.json (`coopnav_ctl summarize`).

    Prints one line per scenario, "<name> <final state>" and why it failed (outcome_failure: a
    contact, a standstill, the time limit, any state but GOAL_REACHED); exits 1 when one failed
    or the file holds no summary, else 0."""
    try:
        doc = json.loads(Path(args.summary).read_text())
        entries = doc["scenarios"]
    except (OSError, ValueError, KeyError, TypeError) as ex:
        print(f"coopnav outcome: {args.summary}: no summary ({ex})", file=sys.stderr)
        return 1
    failed = not entries
    for e in entries:
        why = outcome_failure(e)
        failed = failed or why is not None
        print(f"{e.get('scenario')} {e.get('final_state')}" + (f": {why}" if why else ""))
    return 1 if failed else 0


def _outcome_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("summary", type=Path, help="a summary.json")


outcome_main.add_arguments = _outcome_arguments  # type: ignore[attr-defined]
