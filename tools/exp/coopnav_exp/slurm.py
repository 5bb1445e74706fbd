"""A population or an ablation on a Slurm cluster: the runs as an sbatch array job (docs/slurm.md).

`scripts/coopnav population --slurm ...` generates the scenario files where it is started (a
login node; DIR must be on a file system the compute nodes share), submits one array job of
--slurm-tasks tasks, each running a slice of DIR/jobs.txt (run i goes to task i mod TASKS) -j at
a time on LCM ports of its own, waits for the array to end, and aggregates DIR with the same code
as a local population: the tables are byte for byte those of a local run of the same seed, since
every run is in lockstep and seeded, and its results land in the same DIR/runs/<name>.

Each task's ports: COOPNAV_POP_PORT_BASE + (task * JOBS) mod 20000 + slot. The URL keeps ttl=0,
so a run's multicast never leaves its node, and two tasks on one node use other ports.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shlex
import subprocess
import sys
import time
from pathlib import Path
from typing import Sequence

from . import population as pop

SLURM_DIR = "slurm"  # DIR/slurm: the job script, its options, the tasks' output
PORT_SPAN = 20000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    g = parser.add_argument_group("Slurm (docs/slurm.md)")
    g.add_argument("--slurm", action="store_true",
                   help="run the encounters as an sbatch array job, then aggregate here")
    g.add_argument("--slurm-tasks", type=int, default=None, metavar="T",
                   help="array tasks (default: one per 10 runs)")
    g.add_argument("--slurm-max-running", type=int, default=None, metavar="K",
                   help="at most K tasks at a time (sbatch --array=...%%K)")
    g.add_argument("--slurm-arg", action="append", default=[], metavar="ARG",
                   help="an sbatch option, e.g. --slurm-arg=--partition=short (repeatable)")
    g.add_argument("--slurm-no-wait", action="store_true",
                   help="submit and return; aggregate later with `scripts/coopnav population "
                        "--slurm-aggregate DIR`")
    g.add_argument("--slurm-aggregate", type=Path, default=None, metavar="DIR",
                   help="only aggregate DIR (after a --slurm-no-wait array ended)")


def task_ports(port_base: int, task: int, jobs: int) -> int:
    """The first port of array task `task` (its slots follow)."""
    return port_base + (task * jobs) % PORT_SPAN


def task_slice(n_runs: int, tasks: int, task: int) -> list[int]:
    """The indices in jobs.txt that array task `task` of `tasks` runs."""
    return list(range(task, n_runs, tasks))


def job_script(out: Path) -> str:
    """The sbatch script: every task runs `python3 -m coopnav_exp.slurm task DIR`."""
    env = {"PYTHONPATH": str(pop.ROOT / "tools" / "exp"),
           "COOPNAV_BUILD_DIR": str(pop.build_dir())}
    exports = "".join(f"export {k}={shlex.quote(v)}\n" for k, v in env.items())
    return ("#!/bin/bash\n"
            "# coopnav population: one array task runs its slice of jobs.txt (docs/slurm.md).\n"
            + exports
            + f"exec {shlex.quote(sys.executable)} -m coopnav_exp.slurm task "
            + shlex.quote(str(out)) + "\n")


def submit(out: Path, tasks: int, jobs: int, max_running: int | None,
           extra: Sequence[str]) -> str:
    sdir = out / SLURM_DIR
    script = sdir / "task.sh"
    script.write_text(job_script(out))
    script.chmod(0o755)
    array = f"0-{tasks - 1}" + (f"%{max_running}" if max_running else "")
    cmd = ["sbatch", "--parsable", f"--array={array}", f"--cpus-per-task={jobs}",
           "--job-name=coopnav-pop", f"--output={sdir}/task-%a.out", f"--chdir={out}",
           *extra, str(script)]
    p = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if p.returncode != 0:
        raise RuntimeError(f"sbatch failed ({p.returncode}): {p.stderr.strip()}")
    return p.stdout.strip().split(";")[0]


def job_active(job_id: str) -> bool:
    """True while any task of the array is pending or running (squeue lists it)."""
    p = subprocess.run(["squeue", "-h", "-r", "-j", job_id, "-o", "%i"], capture_output=True,
                       text=True, check=False)
    if p.returncode != 0:
        # squeue forgets a job some time after it ended ("Invalid job id specified").
        return "Invalid job id" not in p.stderr and p.stderr.strip() != ""
    return bool(p.stdout.strip())


def runs_done(out: Path, names: Sequence[str]) -> int:
    return sum((out / "runs" / n / "world_sim.exit").exists() for n in names)


def wait(out: Path, job_id: str, names: Sequence[str], poll_s: float = 2.0) -> None:
    """Waits until the array has left the queue, printing a line whenever more runs are done."""
    shown = -1
    try:
        while job_active(job_id):
            done = runs_done(out, names)
            if done != shown:
                print(f"slurm: job {job_id}: {done}/{len(names)} runs done", flush=True)
                shown = done
            time.sleep(poll_s)
    except KeyboardInterrupt:
        subprocess.run(["scancel", job_id], check=False)
        raise
    print(f"slurm: job {job_id} ended: {runs_done(out, names)}/{len(names)} runs done",
          flush=True)


def _prepare(args: argparse.Namespace, out: Path, n_runs: int) -> tuple[int, Path, int]:
    """The array's task count (--slurm-tasks, else a task per 10 runs), DIR/slurm and the port
    base its tasks start from."""
    tasks = args.slurm_tasks or max(1, math.ceil(n_runs / 10))
    tasks = max(1, min(tasks, n_runs))
    sdir = out / SLURM_DIR
    sdir.mkdir(exist_ok=True)
    return tasks, sdir, int(os.environ.get("COOPNAV_POP_PORT_BASE", "7400"))


def _submit_and_wait(args: argparse.Namespace, out: Path, names: Sequence[str], tasks: int,
                     jobs: int, prog: str, aggregate_hint: str) -> int | None:
    """Submits the array written in DIR/slurm and waits until it has left the queue (then
    DIR/timing.txt), unless --slurm-no-wait. Returns the exit code when the caller must stop
    here (2: not submitted; 0: not waited for), None once the job has ended."""
    start = time.monotonic()
    try:
        job_id = submit(out, tasks, jobs, args.slurm_max_running, args.slurm_arg)
    except (OSError, RuntimeError) as e:
        print(f"{prog}: {e}", file=sys.stderr)
        return 2
    print(f"{prog}: {len(names)} runs as Slurm job {job_id}: {tasks} tasks, {jobs} runs at "
          f"a time each, in {out}", flush=True)
    if args.slurm_no_wait:
        print(f"{prog}: when `squeue -j {job_id}` is empty: {aggregate_hint}")
        return 0
    wait(out, job_id, names)
    wall_s = time.monotonic() - start
    (out / "timing.txt").write_text(
        f"runs {len(names)} jobs {jobs} wall_s {wall_s:.1f} slurm_job {job_id} tasks {tasks}\n")
    print(f"{prog}: {len(names)} runs in {wall_s:.1f} s wall on Slurm", flush=True)
    return None


def run_population(args: argparse.Namespace, out: Path, options: pop.RunOptions,
                   jobs: int) -> int:
    """`population --slurm`: DIR is generated; submit, wait, aggregate."""
    names = [name for name, _, _ in pop.read_jobs(out)]
    tasks, sdir, port_base = _prepare(args, out, len(names))
    (sdir / "options.json").write_text(json.dumps(
        {"tasks": tasks, "jobs": jobs, "port_base": port_base, "run": options.to_dict()},
        indent=1) + "\n")
    rc = _submit_and_wait(args, out, names, tasks, jobs, pop.PROG,
                          f"scripts/coopnav population --slurm-aggregate {out}")
    return pop.aggregate(out) if rc is None else rc


SPECS_FILE = "specs.jsonl"  # DIR/slurm/specs.jsonl: an ablation's runs, one RunSpec a line


def run_specs(args: argparse.Namespace, out: Path, specs: Sequence[pop.RunSpec],
              jobs: int) -> int:
    """`ablation --slurm`: the given runs (each run's folder DIR/runs/<spec name>) as an array
    job, each task a slice of DIR/slurm/specs.jsonl; waits for it unless --slurm-no-wait.
    The caller aggregates."""
    names = [sp.name for sp in specs]
    tasks, sdir, port_base = _prepare(args, out, len(names))
    (sdir / SPECS_FILE).write_text("".join(sp.to_json() + "\n" for sp in specs))
    timeout_s = max((sp.timeout_s for sp in specs), default=900.0)
    (sdir / "options.json").write_text(json.dumps(
        {"tasks": tasks, "jobs": jobs, "port_base": port_base, "specs": SPECS_FILE,
         "timeout_s": timeout_s}, indent=1) + "\n")
    rc = _submit_and_wait(args, out, names, tasks, jobs, "slurm", f"aggregate {out}")
    return 0 if rc is None else rc


def task_main(argv: Sequence[str]) -> int:
    """One array task: `python3 -m coopnav_exp.slurm task DIR` (SLURM_ARRAY_TASK_ID)."""
    out = Path(argv[0]).resolve()
    task = int(os.environ["SLURM_ARRAY_TASK_ID"])
    o = json.loads((out / SLURM_DIR / "options.json").read_text())
    if "specs" in o:  # an ablation's runs, listed
        specs = [pop.RunSpec.from_json(line) for line in
                 (out / SLURM_DIR / o["specs"]).read_text().splitlines() if line]
        options = pop.RunOptions("paper", (), float(o["timeout_s"]))
    else:
        options = pop.RunOptions.from_dict(o["run"])
        specs = pop.run_specs(out, options)
    mine = [specs[i] for i in task_slice(len(specs), o["tasks"], task)]
    pop.lib_sh("coopnav_ensure_multicast")
    base = task_ports(o["port_base"], task, o["jobs"])
    print(f"slurm task {task}: {len(mine)} runs, {o['jobs']} at a time, ports {base}..."
          f"{base + o['jobs'] - 1}, on {os.uname().nodename}", flush=True)
    pop.run_all(out, mine, o["jobs"], base, options.timeout_s)
    return 0


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "task":
        sys.exit(task_main(sys.argv[2:]))
    print("usage: python3 -m coopnav_exp.slurm task DIR (inside an sbatch array task)",
          file=sys.stderr)
    sys.exit(2)
