"""Run a population of generated corridor (or crowd) encounters and tabulate them (docs/population.md).

Generates N scenario files from a seed (tools/population's `coopnav_population generate`), runs
them JOBS at a time, each on an LCM port of its own and in a folder of its own (DIR/runs/<name>),
plus one run without humans per corridor layout (the time-to-goal baseline), and writes
DIR/population.json and DIR/population.txt (`coopnav_population aggregate`). A line per finished
run says where it stands. With --slurm the runs are an sbatch array job instead (docs/slurm.md);
the tables are the same for the same seed.

Exit status: 0; 1 a contact with the robot at fault; 4 a failed dialogue check (words to someone
not crossed, a contradiction, a group told twice, unaddressed among several); 5 a run ended in any
contact, a standstill, the time limit or a mutual wait over 10 s (why on stderr); 3 a run left no
summary (muted twins included); 2 bad arguments, a daemon that rejects its config, bad files.

Environment: COOPNAV_BUILD_DIR (default build), COOPNAV_POP_PORT_BASE (7400: the run in slot k of
JOBS uses port base + k), COOPNAV_POP_RUN_TIMEOUT_S (900: wall seconds before a run and its
daemons are stopped; the run then has no summary).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Sequence

from . import pool as poolmod
from .run import run_one

ROOT = Path(__file__).resolve().parents[3]
PROG = "population"

# The world simulator's overrides of each option (config/world_sim.yaml).
TRACKER_NOISE_ARGS = ["--set", "tracker.position_sigma_m=0.05", "--set",
                      "tracker.miss_probability=0.05", "--set", "tracker.id_switches=1"]
GOALS_WITHHELD_ARGS = ["--set", "publish_human_goals=false"]
REALISTIC_TIMING_ARGS = ["--set", "avoidance_timing=realistic"]
MUTED_ARGS = ["--set", "muted=true"]
# What the aggregation reads of what the humans heard (daemons/world_sim/README.md).
CUE_OUTCOMES_FILE = "cue_outcomes.jsonl"


def build_dir() -> Path:
    return Path(os.environ.get("COOPNAV_BUILD_DIR", str(ROOT / "build"))).resolve()


def population_tool() -> Path:
    return build_dir() / "tools" / "population" / "coopnav_population"


# ---- one run


@dataclasses.dataclass(frozen=True)
class RunSpec:
    """One line of DIR/jobs.txt made concrete: what `run_one` gets (the port comes from the
    pool's slot)."""

    name: str
    scenario: Path
    out_dir: Path
    profile: str
    daemon_args: dict[str, list[str]]
    timeout_s: float
    absent: tuple[str, ...] = ()  # daemons not started (an ablation's variant)

    def to_json(self) -> str:
        return json.dumps({"name": self.name, "scenario": str(self.scenario),
                           "out_dir": str(self.out_dir), "profile": self.profile,
                           "daemon_args": self.daemon_args, "timeout_s": self.timeout_s,
                           "absent": list(self.absent)})

    @staticmethod
    def from_json(text: str) -> "RunSpec":
        d = json.loads(text)
        return RunSpec(d["name"], Path(d["scenario"]), Path(d["out_dir"]), d["profile"],
                       {k: list(v) for k, v in d["daemon_args"].items()}, float(d["timeout_s"]),
                       tuple(d.get("absent", ())))


@dataclasses.dataclass(frozen=True)
class RunOptions:
    """What every run of a population shares (the command line's options)."""

    profile: str = "paper"
    world_sim_args: tuple[str, ...] = ()
    timeout_s: float = 900.0

    def to_dict(self) -> dict:
        return {"profile": self.profile, "world_sim_args": list(self.world_sim_args),
                "timeout_s": self.timeout_s}

    @staticmethod
    def from_dict(d: dict) -> "RunOptions":
        return RunOptions(d["profile"], tuple(d["world_sim_args"]), float(d["timeout_s"]))


def read_jobs(out: Path) -> list[tuple[str, str, str]]:
    """DIR/jobs.txt: `name<TAB>scenario[<TAB>muted]` a line (tools/population/README.md)."""
    jobs = []
    for line in (out / "jobs.txt").read_text().splitlines():
        if not line:
            continue
        fields = line.split("\t")
        jobs.append((fields[0], fields[1], fields[2] if len(fields) > 2 else ""))
    return jobs


def run_specs(out: Path, options: RunOptions) -> list[RunSpec]:
    """The runs of population folder `out`, in jobs.txt's order. A muted twin runs its
    encounter's file with the dialogue manager deciding and acting as usual but saying nothing."""
    specs = []
    for name, scenario, mode in read_jobs(out):
        run_dir = out / "runs" / name
        args = {"world_sim": list(options.world_sim_args)
                + ["--set", f"cue_outcomes_file={run_dir / CUE_OUTCOMES_FILE}"]}
        if mode == "muted":
            args["dialogue_manager"] = list(MUTED_ARGS)
        specs.append(RunSpec(name, out / scenario, run_dir, options.profile, args,
                             options.timeout_s))
    return specs


def worker_main(argv: Sequence[str]) -> int:
    """`python3 -m coopnav_exp.population worker SPEC_JSON PORT`: one run in a process of its own
    (the pool stops it and its daemons at the wall timeout: SIGTERM ends it through run_one's
    cleanup)."""
    spec = RunSpec.from_json(argv[0])
    port = int(argv[1])

    def on_term(signum, _frame):
        raise SystemExit(128 + signum)

    signal.signal(signal.SIGTERM, on_term)
    # Stamped as the daemons stamp their logs, to tell start-up and teardown from simulation.
    print(f"[{_stamp()}] worker: {spec.name} on port {port}", flush=True)
    shutil.rmtree(spec.out_dir, ignore_errors=True)
    spec.out_dir.mkdir(parents=True)
    result = run_one(spec.scenario, spec.out_dir, port, profile=spec.profile,
                        daemon_args=spec.daemon_args, absent=spec.absent,
                        timeout_s=spec.timeout_s)
    (spec.out_dir / "world_sim.exit").write_text(f"{result.world_sim_exit}\n")
    print(f"[{_stamp()}] worker: {spec.name} done, world_sim exit {result.world_sim_exit}",
          flush=True)
    return 0


def _stamp() -> str:
    now = time.time()
    return time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(now)) + f".{int(now % 1 * 1000):03d}"


def summary_state(run_dir: Path) -> tuple[str, float | None]:
    """The final state and simulated seconds of a run from its summary.json (NO_SUMMARY, None
    without one)."""
    try:
        doc = json.loads((run_dir / "summary.json").read_text())
        first = doc["scenarios"][0]
    except (OSError, ValueError, KeyError, IndexError, TypeError):
        return "NO_SUMMARY", None
    state = first.get("final_state") or "NO_SUMMARY"
    sim = first.get("sim_time_s")
    return str(state), float(sim) if isinstance(sim, (int, float)) else None


def run_all(out: Path, specs: Sequence[RunSpec], jobs: int, port_base: int, timeout_s: float,
            stream=None) -> float:
    """Runs `specs` `jobs` at a time with a progress line per finished run; returns the wall
    seconds. Each worker's own output goes to DIR/workers/<name>.log."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(ROOT / "tools" / "exp")] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep)
                                         if p])

    def job(spec: RunSpec) -> poolmod.Job:
        def command(port: int) -> list[str]:
            return [sys.executable, "-m", "coopnav_exp.population", "worker", spec.to_json(),
                    str(port)]
        return poolmod.Job(spec.name, command, out / "workers" / f"{spec.name}.log", env)

    progress = poolmod.Progress(len(specs), stream)

    def finished(r: poolmod.Finished, done: int, _total: int) -> None:
        state, sim_s = summary_state(out / "runs" / r.job.name)
        progress.show(done, r.job.name, state, sim_s, r.wall_s)

    start = time.monotonic()
    poolmod.Pool(jobs, port_base, timeout_s).run([job(s) for s in specs], finished)
    progress.end()
    return time.monotonic() - start


# ---- the population


def add_arguments(parser: argparse.ArgumentParser) -> None:
    # Checked in main, in this order, with the messages population.sh has always given.
    parser.add_argument("--n", default="200", help="encounters (default 200)")
    parser.add_argument("--seed", default="1", help="population seed (default 1)")
    parser.add_argument("-j", dest="jobs", default=None,
                        help="runs at a time (default: cores; at most 4 per core)")
    parser.add_argument("--out", type=Path, default=None,
                        help="folder (default runs/population-<seed>[-cue|-crowd])")
    parser.add_argument("--no-build", dest="build", action="store_false",
                        help="use the build as it is")
    parser.add_argument("--tracker-noise", action="store_true",
                        help="the humans as a tracker sees them: sigma 0.05 m, 5 %% missed, "
                             "one id switch")
    parser.add_argument("--goals-withheld", action="store_true",
                        help="the humans' goals are not published; the band source infers them")
    parser.add_argument("--realistic-timing", action="store_true",
                        help="people who yield of their own accord start at an onset drawn from "
                             "real walkers' (world_sim avoidance_timing=realistic)")
    parser.add_argument("--profile", default=os.environ.get("COOPNAV_PROFILE", "paper"),
                        metavar="PROFILE",
                        help="a profile of config/system.yaml: paper, calibrated, forecast or make_time "
                             "(as scripts/run.sh)")
    parser.add_argument("--slower-ahead", action="store_true",
                        help="every encounter has a slower person ahead walking the robot's way")
    parser.add_argument("--pause", action="store_true",
                        help="in every encounter one of the people pauses on the way")
    parser.add_argument("--max-width-m", default=None, metavar="W",
                        help="only the corridors no wider than W m (a study of narrow ones)")
    kind = parser.add_mutually_exclusive_group()
    kind.add_argument("--cue-effect", action="store_true",
                      help="every head-on human responsive, every encounter also run muted")
    kind.add_argument("--crowd", action="store_true", help="crowd encounters, 2-10 people")
    from . import slurm
    slurm.add_arguments(parser)


def _fail(message: str) -> int:
    print(f"{PROG}: {message}", file=sys.stderr)
    return 2


def run_options(args: argparse.Namespace) -> RunOptions:
    world = []
    if args.tracker_noise:
        world += TRACKER_NOISE_ARGS
    if args.goals_withheld:
        world += GOALS_WITHHELD_ARGS
    if args.realistic_timing:
        world += REALISTIC_TIMING_ARGS
    return RunOptions(args.profile, tuple(world),
                      float(os.environ.get("COOPNAV_POP_RUN_TIMEOUT_S", "900")))


def output_dir(args: argparse.Namespace) -> Path:
    if args.out is not None:
        out = args.out
    else:
        suffix = "-cue" if args.cue_effect else "-crowd" if args.crowd else ""
        out = ROOT / "runs" / f"population-{args.seed}{suffix}"
    out.mkdir(parents=True, exist_ok=True)
    return out.resolve()


def lib_sh(commands: str) -> int:
    """Runs bash functions of scripts/lib.sh (the dependency install, the build, the multicast
    route)."""
    return subprocess.run(["bash", "-c", f'source "{ROOT}/scripts/lib.sh"; {commands}'],
                          check=False).returncode


def daemon_names() -> list[str]:
    """The daemons of a run and the world, as config/system.yaml describes them."""
    from . import system as system_mod
    s = system_mod.load()
    return s.names() + [s.world.name]


def check_configs(cue_effect: bool) -> str | None:
    """A daemon older than its config (keys added since it was built) would only fail at each
    run: every daemon loads its config first. Returns what is wrong, or None."""
    checks = [(d, []) for d in daemon_names()]
    if cue_effect:
        checks.append(("dialogue_manager", MUTED_ARGS))
    for d, extra in checks:
        exe = build_dir() / "daemons" / d / f"coopnav_{d}"
        p = subprocess.run([str(exe), "-c", str(ROOT / "config" / f"{d}.yaml"), *extra,
                            "--print-config"], capture_output=True, text=True, check=False)
        if p.returncode != 0:
            return (f"{d} rejects config/{d}.yaml {' '.join(extra)}(rebuild {build_dir()}?):\n"
                    + p.stderr.strip())
    return None


def generate(args: argparse.Namespace, out: Path) -> int:
    gen = [str(population_tool()), "generate", "--n", str(args.n), "--seed", str(args.seed),
           "--out", str(out), "--maps-dir", str(ROOT / "config" / "maps")]
    if args.cue_effect:
        gen += ["--behaviour", "responsive", "--cue-effect"]
    if args.crowd:
        gen += ["--crowd"]
    if getattr(args, "slower_ahead", False):
        gen += ["--slower-ahead"]
    if getattr(args, "pause", False):
        gen += ["--pause"]
    if getattr(args, "max_width_m", None):
        gen += ["--max-width-m", str(args.max_width_m)]
    return subprocess.run(gen, check=False).returncode


def aggregate(out: Path) -> int:
    rc = subprocess.run([str(population_tool()), "aggregate", "--dir", str(out)],
                        check=False).returncode
    print(f"{PROG}: {out / 'population.txt'}, {out / 'population.json'}")
    return rc


def default_jobs() -> int:
    return os.cpu_count() or 1


def prepare(args: argparse.Namespace) -> tuple[int, Path | None]:
    """Build, multicast route, config check, generation: (exit status, population folder)."""
    if args.build and lib_sh("coopnav_install_deps; coopnav_build") != 0:
        return _fail("the build failed"), None
    lib_sh("coopnav_ensure_multicast")
    if (problem := check_configs(args.cue_effect)) is not None:
        return _fail(problem), None
    out = output_dir(args)
    if generate(args, out) != 0:
        return _fail("coopnav_population generate failed"), None
    return 0, out


def check_arguments(args: argparse.Namespace) -> str | None:
    """What is wrong with the options (None: nothing); args.n, .seed, .jobs become integers."""
    if args.jobs is not None and not (args.jobs.isdigit() and int(args.jobs) > 0):
        return "-j needs a positive integer"
    if not args.n.isdigit():
        return f"--n needs a count, not '{args.n}'"
    if not args.seed.isdigit():
        return f"--seed needs an integer, not '{args.seed}'"
    args.n, args.seed = int(args.n), int(args.seed)
    # On Slurm, -j is per array task (its --cpus-per-task): one run by default.
    args.jobs = int(args.jobs) if args.jobs else (1 if args.slurm else default_jobs())
    # Each run is seven processes stepping in lockstep: past a few runs per core they only wait
    # on each other and every run slows towards the timeout; each slot takes a port of its own.
    max_jobs = 4 * default_jobs()
    if args.jobs > max_jobs and not args.slurm:
        print(f"{PROG}: -j {args.jobs} capped to {max_jobs} (4 runs per core)", file=sys.stderr)
        args.jobs = max_jobs
    from . import system as system_mod
    profiles = system_mod.load().profiles
    if args.profile not in profiles:
        return f"--profile must be {system_mod.one_of(profiles)}, not '{args.profile}'"
    return None


def main(args: argparse.Namespace) -> int:
    if args.slurm_aggregate is not None:
        return aggregate(args.slurm_aggregate.resolve())
    if (problem := check_arguments(args)) is not None:
        return _fail(problem)
    jobs = args.jobs
    rc, out = prepare(args)
    if out is None:
        return rc
    options = run_options(args)
    if args.slurm:
        from . import slurm
        return slurm.run_population(args, out, options, jobs)
    specs = run_specs(out, options)
    print(f"{PROG}: {len(specs)} runs, {jobs} at a time, in {out}", flush=True)
    wall_s = run_all(out, specs, jobs, int(os.environ.get("COOPNAV_POP_PORT_BASE", "7400")),
                     options.timeout_s)
    (out / "timing.txt").write_text(f"runs {len(specs)} jobs {jobs} wall_s {wall_s:.1f}\n")
    print(f"{PROG}: {len(specs)} runs in {wall_s:.1f} s wall with -j {jobs}", flush=True)
    return aggregate(out)


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "worker":
        sys.exit(worker_main(sys.argv[2:]))
    print("usage: python3 -m coopnav_exp.population worker SPEC_JSON PORT "
          "(the population itself: scripts/coopnav population)", file=sys.stderr)
    sys.exit(2)
