"""Run the same generated encounters under named variants and compare them (docs/ablation.md).

`scripts/coopnav ablation [--encounters N] [--seed S] [--variants a,b,...] [-j JOBS] [--out DIR]
[--slurm ...]` generates N encounters exactly as a population of that seed does
(`coopnav_population generate`, the robot-alone baselines left out), runs every encounter under
every variant of config/system.yaml's `variants` (default: all of them, `planner_only` first:
the band planner alone, no assessment and no words), scores each run from its log (run_one's
metrics.json, docs/metrics.md) and writes DIR/ablation.md, .csv and .json: per variant every
metric with its 95 % interval (Wilson for proportions, percentile bootstrap for means), and per
variant against the reference (`planner_only` when it runs, else the first variant) on the
encounters both ran, the mean difference with its paired-bootstrap interval and the p-value (exact
McNemar for outcomes, Wilcoxon signed-rank for the rest); figures DIR/ablation_metrics and
DIR/ablation_paired (PNG and SVG) and, per variant that assesses, DIR/agreement_<variant>
(Responsibility against CM).

Runs go to DIR/runs/<variant>/<encounter>, JOBS at a time, each on an LCM port of its own
(COOPNAV_POP_PORT_BASE + slot, as a population's); with --slurm they are an sbatch array job
(docs/slurm.md). A variant that leaves lockstep daemons out runs the encounter's scenario with them
removed from its lockstep participants (DIR/scenarios-<variant>/, byte for byte the same file
otherwise). The tables hold no wall time, path or date: the same seed gives the same files
whether the runs ran here or on a cluster. `--aggregate DIR` only tabulates an existing DIR;
`--resume` keeps the runs DIR already holds for the same seed, variant definition and scenario
bytes (an interrupted study goes on; a larger --encounters of the same seed extends one, the
generator giving the first encounters the same files).

Exit status: 0 tables written; 2 bad arguments, a daemon that rejects its config, a failed
generation or build; 3 a run left no metrics (the tables are written without it, the missing runs
named in them and on stderr).
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import io
import json
import math
import os
import re
import sys
from pathlib import Path
from typing import Sequence

from . import metrics, stats
from . import population as pop
from . import system as system_mod

PROG = "ablation"
REFERENCE = "planner_only"
PLAN_FILE = "ablation_plan.json"
FORMAT = "coopnav-ablation/1"

# The metrics of the Markdown table and the figures (every metric is in the CSV and JSON):
# (part, key) with part "metrics" (per run) or "persons" (per person crossed).
HEADLINE: list[tuple[str, str]] = [
    ("metrics", "success"),
    ("metrics", "collision"),
    ("metrics", "failure_to_progress"),
    ("metrics", "timeout"),
    ("metrics", "time_to_goal_s"),
    ("metrics", "spl"),
    ("metrics", "path_length_ratio"),
    ("metrics", "stalled_s"),
    ("metrics", "min_distance_to_person_m"),
    ("metrics", "intimate_s"),
    ("metrics", "personal_s"),
    ("metrics", "social_work"),
    ("persons", "robot_responsibility"),
]


# ---- the plan: encounters, variants, runs


def encounters_of(out: Path) -> list[str]:
    """The generated encounters of DIR/jobs.txt, in its order: the robot-alone baselines and
    muted twins left out (an ablation's variants replace them)."""
    return [name for name, _, mode in pop.read_jobs(out)
            if not name.startswith("base_") and mode == ""]


def variant_scenario(source: Path, absent_lockstep: Sequence[str], dest: Path) -> Path:
    """`source` with `absent_lockstep` left out of its lockstep participants, written to `dest`
    (every other byte the same, so the encounter is the same; world_sim then waits for no step
    acknowledgement of a daemon that is not there)."""
    text = source.read_text()
    pattern = re.compile(r"^(\s*participants:\s*)\[([^\]]*)\](.*)$", re.M)
    matches = pattern.findall(text)
    if len(matches) != 1:
        raise ValueError(f"{source}: expected one 'participants: [...]' line, found "
                         f"{len(matches)}")

    def keep(m: re.Match) -> str:
        names = [n.strip() for n in m.group(2).split(",") if n.strip()]
        return m.group(1) + "[" + ", ".join(n for n in names if n not in absent_lockstep) + "]" \
            + m.group(3)

    dest.parent.mkdir(parents=True, exist_ok=True)
    dest.write_text(pattern.sub(keep, text))
    return dest


def run_specs(out: Path, variants: Sequence[system_mod.Variant], encounters: Sequence[str],
              s: system_mod.System, options: pop.RunOptions) -> list[pop.RunSpec]:
    """Every (encounter, variant) run, encounter by encounter (a study cut short still has
    pairs), each in DIR/runs/<variant>/<encounter>."""
    lockstep = set(s.lockstep_names())
    specs = []
    for enc in encounters:
        source = out / "scenarios" / f"{enc}.yaml"
        for v in variants:
            absent_lockstep = [d for d in v.absent if d in lockstep]
            scenario = source
            if absent_lockstep:
                scenario = variant_scenario(source, absent_lockstep,
                                            out / f"scenarios-{v.name}" / f"{enc}.yaml")
            args = {k: list(a) for k, a in v.args.items()}
            args["world_sim"] = list(options.world_sim_args) + args.get("world_sim", [])
            specs.append(pop.RunSpec(f"{v.name}/{enc}", scenario, out / "runs" / v.name / enc,
                                     v.profile, args, options.timeout_s, tuple(v.absent)))
    return specs


def _digest(path: Path) -> str | None:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return None


def scenario_digests(out: Path) -> dict[str, str]:
    """The digest of each encounter's scenario file in DIR/scenarios (before generating again)."""
    d = out / "scenarios"
    return {p.stem: h for p in sorted(d.glob("*.yaml")) if (h := _digest(p)) is not None} \
        if d.is_dir() else {}


def variant_entry(v: system_mod.Variant) -> dict:
    """A variant as the plan records it (what a kept run must have been run with)."""
    return {"name": v.name, "description": v.description, "profile": v.profile,
            "absent": list(v.absent), "args": {k: list(a) for k, a in v.args.items()}}


def kept_runs(out: Path, specs: Sequence[pop.RunSpec], before: dict[str, str],
              old_plan: dict | None, variants: Sequence[system_mod.Variant],
              timing_args: Sequence[str]) -> set[str]:
    """--resume: the runs already done in DIR that need not run again: each left its metrics and
    exit status, its encounter's scenario file is byte for byte the one generated now (`before`:
    the digests of the files it ran), and its variant and the world's options are the plan's."""
    if not old_plan:
        return set()
    old_variants = {v["name"]: v for v in old_plan.get("variants", [])}
    if bool(old_plan.get("realistic_timing")) != bool(timing_args):
        return set()
    same = {v.name for v in variants if old_variants.get(v.name) == variant_entry(v)}
    kept = set()
    for sp in specs:
        variant, enc = sp.name.split("/", 1)
        source = out / "scenarios" / f"{enc}.yaml"
        if (variant in same and before.get(enc) is not None
                and before.get(enc) == _digest(source)
                and (sp.out_dir / metrics.RUN_METRICS_FILE).is_file()
                and (sp.out_dir / "world_sim.exit").is_file()):
            kept.add(sp.name)
    return kept


# ---- aggregation (pure: the same files give the same tables)


def load_variant_runs(out: Path, variant: str, encounters: Sequence[str],
                      ctl: Path | None = None) -> tuple[list[dict], list[str]]:
    """The metrics of each encounter's run of `variant` (run_one's metrics.json; a log without
    one is scored now), its `scenario` set to the encounter; and the encounters without any."""
    runs, missing = [], []
    for enc in encounters:
        d = out / "runs" / variant / enc
        f = d / metrics.RUN_METRICS_FILE
        if not f.is_file() and (d / f"{enc}.lcm").is_file() and ctl is not None:
            try:
                f = metrics.score_log(d / f"{enc}.lcm", ctl)
            except RuntimeError:
                pass
        try:
            got = metrics.load_runs([f]) if f.is_file() else []
        except (OSError, ValueError):
            got = []
        if len(got) != 1:
            missing.append(enc)
            continue
        run = dict(got[0])
        run["scenario"] = enc
        runs.append(run)
    return runs, missing


def reference_of(names: Sequence[str]) -> str:
    return REFERENCE if REFERENCE in names else names[0]


def aggregate(variant_runs: dict[str, list[dict]], *, seed: int = stats.DEFAULT_SEED,
              n_boot: int = stats.DEFAULT_N_BOOT) -> dict:
    """Per variant the metrics table (metrics.aggregate), and every other variant against the
    reference on the same encounters (metrics.paired_table)."""
    names = list(variant_runs)
    ref = reference_of(names)
    ordered = {ref: variant_runs[ref], **{n: variant_runs[n] for n in names if n != ref}}
    tables = {n: metrics.aggregate(runs, seed=seed, n_boot=n_boot) for n, runs in ordered.items()}
    paired = metrics.paired_table(ordered, seed=seed, n_boot=n_boot) if len(ordered) > 1 else []
    return {"reference": ref, "tables": tables, "paired": paired}


def _row(table: dict, part: str, key: str) -> dict | None:
    return next((r for r in table[part] if r["key"] == key), None)


def _label(part: str, key: str) -> str:
    pool = metrics.RUN_METRICS if part == "metrics" else [(k, "mean", lab) for k, lab in
                                                         metrics.PERSON_METRICS]
    return next(lab for k, _, lab in pool if k == key)


def _f(v: float | None, digits: int = 3) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    return f"{v:.{digits}f}"


def _p(v: float | None) -> str:
    if v is None:
        return "–"
    return "< 0.001" if v < 0.001 else f"{v:.3f}"


def markdown(doc: dict) -> str:
    """The comparison table of ablation.json as Markdown (the headline metrics)."""
    res = doc["result"]
    names = list(res["tables"])
    ref = res["reference"]
    lines = [f"# Ablation: {doc['encounters']} encounters (population seed {doc['seed']}) × "
             f"{len(names)} variants", "",
             f"95 % intervals: Wilson for proportions, percentile bootstrap of the mean (seed "
             f"{doc['bootstrap_seed']}, {doc['n_boot']} resamples) otherwise. n: runs (or persons) "
             "with a value.", "", "| variant | description | runs scored | missing |",
             "|---|---|---|---|"]
    for n in names:
        v = doc["variants"][n]
        lines.append(f"| `{n}` | {v['description']} | {res['tables'][n]['runs']} | "
                     f"{', '.join(v['missing']) or '–'} |")
    lines += ["", "## Per variant", "",
              "| metric | " + " | ".join(f"`{n}`" for n in names) + " |",
              "|---|" + "---|" * len(names)]
    for part, key in HEADLINE:
        cells = []
        for n in names:
            r = _row(res["tables"][n], part, key)
            cells.append("–" if r is None or r["value"] is None else
                         f"{_f(r['value'])} [{_f(r['lo'])}, {_f(r['hi'])}] (n {r['n']})")
        lines.append(f"| {_label(part, key)} | " + " | ".join(cells) + " |")
    others = [n for n in names if n != ref]
    if others and res["paired"]:
        lines += ["", f"## Against `{ref}` on the same encounters", "",
                  f"Mean difference variant − `{ref}` over the encounters (persons) both have a "
                  "value for, its paired-bootstrap 95 % interval, and the p-value (exact McNemar "
                  "for outcomes, Wilcoxon signed-rank otherwise).", "",
                  "| metric | " + " | ".join(f"`{n}` − `{ref}`" for n in others) + " |",
                  "|---|" + "---|" * len(others)]
        for part, key in HEADLINE:
            cells = []
            for n in others:
                r = next((x for x in res["paired"] if x["variant"] == n and x["key"] == key),
                         None)
                if r is None or r["difference"] is None:
                    cells.append("–")
                else:
                    cells.append(f"{_f(r['difference'], 3)} [{_f(r['lo'])}, {_f(r['hi'])}] "
                                 f"p {_p(r['p_value'])} ({r['n_pairs']} pairs)")
            lines.append(f"| {_label(part, key)} | " + " | ".join(cells) + " |")
    agreement = [(n, t["agreement"]) for n, t in res["tables"].items()
                 if any(a["value"] is not None for a in t["agreement"])]
    if agreement:
        lines += ["", "## Responsibility against CM", "",
                  "| variant | " + " | ".join(a["label"] for a in agreement[0][1]) + " |",
                  "|---|" + "---|" * len(agreement[0][1])]
        for n, rows in agreement:
            lines.append(f"| `{n}` | " + " | ".join(
                f"{_f(a['value'])} [{_f(a['lo'])}, {_f(a['hi'])}] (n {a['n']})" for a in rows)
                + " |")
    return "\n".join(lines) + "\n"


def to_csv(doc: dict) -> str:
    """Every row of every table, long format: section, variant, reference, key, label, method,
    value, lo, hi, n, p_value."""
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["section", "variant", "reference", "key", "label", "method", "value", "lo", "hi",
                "n", "p_value"])

    def num(v):
        return "" if v is None else repr(v)

    res = doc["result"]
    for n, t in res["tables"].items():
        for part in ("metrics", "persons", "agreement"):
            for r in t[part]:
                w.writerow([part, n, "", r["key"], r["label"], r["method"], num(r["value"]),
                            num(r["lo"]), num(r["hi"]), r["n"], ""])
    for r in res["paired"]:
        w.writerow(["paired", r["variant"], r["reference"], r["key"], r["label"],
                    r["test"] or "", num(r["difference"]), num(r["lo"]), num(r["hi"]),
                    r["n_pairs"], num(r["p_value"])])
    return out.getvalue()


def document(out: Path, *, seed: int, n_boot: int, bootstrap_seed: int,
             ctl: Path | None = None) -> dict:
    """ablation.json of DIR: its plan, the variants' missing runs and the tables."""
    plan = json.loads((out / PLAN_FILE).read_text())
    encounters = plan["encounters"]
    runs, variants = {}, {}
    for v in plan["variants"]:
        runs[v["name"]], missing = load_variant_runs(out, v["name"], encounters, ctl)
        variants[v["name"]] = {**v, "missing": missing}
    return {"format": FORMAT, "seed": seed, "encounters": len(encounters),
            "bootstrap_seed": bootstrap_seed, "n_boot": n_boot, "variants": variants,
            "result": aggregate(runs, seed=bootstrap_seed, n_boot=n_boot)}


# ---- figures


def _style(ax, variants: Sequence[str], part: str, key: str) -> None:
    """One headline metric's panel: the variants along x, the metric's name above."""
    ax.set_xticks(range(len(variants)))
    ax.set_xticklabels(variants, rotation=35, ha="right", fontsize=7)
    ax.set_title(_label(part, key), fontsize=8)
    ax.tick_params(axis="y", labelsize=7)
    ax.grid(axis="y", alpha=0.3)


def figures(doc: dict, out: Path) -> list[Path]:
    """ablation_metrics (per variant, each headline metric with its interval) and
    ablation_paired (each variant's difference from the reference with its interval)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .figures import save

    res = doc["result"]
    names = list(res["tables"])
    written: list[Path] = []
    cols = 4
    rows_n = math.ceil(len(HEADLINE) / cols)
    fig, axes = plt.subplots(rows_n, cols, figsize=(3.2 * cols, 2.6 * rows_n), squeeze=False)
    for ax, (part, key) in zip(axes.flat, HEADLINE):
        for i, n in enumerate(names):
            r = _row(res["tables"][n], part, key)
            if r is None or r["value"] is None:
                continue
            lo = r["value"] - (r["lo"] if r["lo"] is not None else r["value"])
            hi = (r["hi"] if r["hi"] is not None else r["value"]) - r["value"]
            ax.errorbar([i], [r["value"]], yerr=[[lo], [hi]], fmt="o", capsize=3,
                        color="#7f7f7f" if n == res["reference"] else "#1f77b4")
        _style(ax, names, part, key)
    for ax in list(axes.flat)[len(HEADLINE):]:
        ax.set_visible(False)
    fig.suptitle(f"{doc['encounters']} encounters (seed {doc['seed']}) per variant, 95 % "
                 "intervals", fontsize=9)
    fig.tight_layout()
    written += save(fig, out / "ablation_metrics")
    plt.close(fig)

    others = [n for n in names if n != res["reference"]]
    if others and res["paired"]:
        fig, axes = plt.subplots(rows_n, cols, figsize=(3.2 * cols, 2.6 * rows_n), squeeze=False)
        for ax, (part, key) in zip(axes.flat, HEADLINE):
            for i, n in enumerate(others):
                r = next((x for x in res["paired"] if x["variant"] == n and x["key"] == key),
                         None)
                if r is None or r["difference"] is None:
                    continue
                d = r["difference"]
                lo, hi = d - (r["lo"] if r["lo"] is not None else d), \
                    (r["hi"] if r["hi"] is not None else d) - d
                sure = r["p_value"] is not None and r["p_value"] < 0.05
                ax.errorbar([i], [d], yerr=[[lo], [hi]], fmt="o", capsize=3,
                            color="#d62728" if sure else "#1f77b4")
            ax.axhline(0.0, color="#404040", lw=0.8)
            _style(ax, others, part, key)
        for ax in list(axes.flat)[len(HEADLINE):]:
            ax.set_visible(False)
        fig.suptitle(f"difference from {res['reference']} on the same encounters, 95 % "
                     "paired-bootstrap intervals (red: p < 0.05)", fontsize=9)
        fig.tight_layout()
        written += save(fig, out / "ablation_paired")
        plt.close(fig)
    return written


def write_outputs(out: Path, doc: dict, *, draw: bool = True) -> list[Path]:
    files = [out / "ablation.json", out / "ablation.csv", out / "ablation.md"]
    files[0].write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    files[1].write_text(to_csv(doc), encoding="utf-8")
    files[2].write_text(markdown(doc), encoding="utf-8")
    if draw:
        files += figures(doc, out)
        plan = json.loads((out / PLAN_FILE).read_text())
        for v in plan["variants"]:
            runs, _ = load_variant_runs(out, v["name"], plan["encounters"])
            files += metrics.agreement_figure(runs, out / f"agreement_{v['name']}",
                                              title=f"{v['name']}, {len(runs)} encounters",
                                              seed=doc["bootstrap_seed"], n_boot=doc["n_boot"])
    return files


# ---- the command


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--encounters", default="40", help="encounters (default 40)")
    parser.add_argument("--seed", default="1", help="population seed (default 1)")
    parser.add_argument("--variants", default=None,
                        help="comma-separated variants of config/system.yaml (default: all)")
    parser.add_argument("-j", "--jobs", dest="jobs", default=None,
                        help="runs at a time (default: cores; on Slurm per array task, 1)")
    parser.add_argument("--out", type=Path, default=None,
                        help="folder (default runs/ablation-<seed>)")
    parser.add_argument("--no-build", dest="build", action="store_false",
                        help="use the build as it is")
    parser.add_argument("--realistic-timing", action="store_true",
                        help="people who yield of their own accord start at an onset drawn from "
                             "real walkers' (world_sim avoidance_timing=realistic)")
    parser.add_argument("--resume", action="store_true",
                        help="keep the runs DIR already holds for the same seed, variant and "
                             "scenario file (an interrupted study, or more --encounters)")
    parser.add_argument("--aggregate", type=Path, default=None, metavar="DIR",
                        help="only tabulate DIR (its runs as they are)")
    parser.add_argument("--no-figures", dest="figures", action="store_false",
                        help="tables only")
    parser.add_argument("--bootstrap-seed", type=int, default=stats.DEFAULT_SEED,
                        help="bootstrap seed (default %(default)s)")
    parser.add_argument("--n-boot", type=int, default=stats.DEFAULT_N_BOOT,
                        help="bootstrap resamples (default %(default)s)")
    from . import slurm
    slurm.add_arguments(parser)


def _fail(message: str) -> int:
    print(f"{PROG}: {message}", file=sys.stderr)
    return 2


def choose_variants(s: system_mod.System, text: str | None) -> list[system_mod.Variant]:
    """The variants named (all by default), the reference first; ValueError names a bad one."""
    names = list(s.variants) if text is None else [n.strip() for n in text.split(",")
                                                    if n.strip()]
    if not names:
        raise ValueError("--variants names no variant")
    for n in names:
        if n not in s.variants:
            raise ValueError(f"--variants: no variant '{n}' in {s.path} "
                             f"(variants: {system_mod.one_of(s.variants)})")
    if len(set(names)) != len(names):
        raise ValueError("--variants names a variant twice")
    ref = reference_of(names)
    return [s.variants[ref]] + [s.variants[n] for n in names if n != ref]


def tabulate(out: Path, args: argparse.Namespace) -> int:
    plan = json.loads((out / PLAN_FILE).read_text())
    doc = document(out, seed=plan["seed"], n_boot=args.n_boot, bootstrap_seed=args.bootstrap_seed,
                   ctl=metrics.default_ctl())
    files = write_outputs(out, doc, draw=args.figures)
    sys.stdout.write(markdown(doc))
    print(f"{PROG}: {', '.join(str(f) for f in files[:3])}"
          + (f" and {len(files) - 3} figure files" if len(files) > 3 else ""))
    missing = [f"{n}/{e}" for n, v in doc["variants"].items() for e in v["missing"]]
    if missing:
        print(f"{PROG}: {len(missing)} runs left no metrics: {' '.join(missing)}",
              file=sys.stderr)
        return 3
    return 0


def main(args: argparse.Namespace) -> int:
    agg = args.aggregate or args.slurm_aggregate
    if agg is not None:
        if not (agg / PLAN_FILE).is_file():
            return _fail(f"{agg} holds no {PLAN_FILE} (not an ablation folder)")
        return tabulate(agg.resolve(), args)
    if not args.encounters.isdigit() or int(args.encounters) < 1:
        return _fail(f"--encounters needs a positive count, not '{args.encounters}'")
    if not args.seed.isdigit():
        return _fail(f"--seed needs an integer, not '{args.seed}'")
    if args.jobs is not None and not (args.jobs.isdigit() and int(args.jobs) > 0):
        return _fail("-j needs a positive integer")
    n, seed = int(args.encounters), int(args.seed)
    jobs = int(args.jobs) if args.jobs else (1 if args.slurm else pop.default_jobs())
    try:
        s = system_mod.load()
        variants = choose_variants(s, args.variants)
    except (system_mod.SystemConfigError, ValueError) as e:
        return _fail(str(e))
    if args.build and pop.lib_sh("coopnav_install_deps; coopnav_build") != 0:
        return _fail("the build failed")
    pop.lib_sh("coopnav_ensure_multicast")
    if (problem := pop.check_configs(cue_effect=True)) is not None:
        return _fail(problem)
    out = (args.out or pop.ROOT / "runs" / f"ablation-{seed}")
    out.mkdir(parents=True, exist_ok=True)
    out = out.resolve()
    old_plan = None
    if args.resume and (out / PLAN_FILE).is_file():
        old_plan = json.loads((out / PLAN_FILE).read_text())
        if old_plan.get("seed") != seed:
            return _fail(f"--resume: {out} holds seed {old_plan.get('seed')}, not {seed}")
    before = scenario_digests(out) if args.resume else {}
    gen = argparse.Namespace(n=n, seed=seed, cue_effect=False, crowd=False)
    if pop.generate(gen, out) != 0:
        return _fail("coopnav_population generate failed")
    encounters = encounters_of(out)
    realistic = pop.REALISTIC_TIMING_ARGS if args.realistic_timing else []
    options = pop.RunOptions("paper", tuple(realistic),
                             float(os.environ.get("COOPNAV_POP_RUN_TIMEOUT_S", "900")))
    specs = run_specs(out, variants, encounters, s, options)
    kept = kept_runs(out, specs, before, old_plan, variants, realistic)
    (out / PLAN_FILE).write_text(json.dumps({
        "seed": seed, "encounters": encounters, "realistic_timing": args.realistic_timing,
        "variants": [variant_entry(v) for v in variants]}, indent=1) + "\n")
    if kept:
        print(f"{PROG}: --resume: {len(kept)} runs already done are kept", flush=True)
        specs = [sp for sp in specs if sp.name not in kept]
    if args.slurm and specs:
        from . import slurm
        rc = slurm.run_specs(args, out, specs, jobs)
        if rc != 0 or args.slurm_no_wait:
            if args.slurm_no_wait and rc == 0:
                print(f"{PROG}: then scripts/coopnav ablation --aggregate {out}")
            return rc
    elif specs:
        print(f"{PROG}: {len(encounters)} encounters × {len(variants)} variants: {len(specs)} "
              f"runs, {jobs} at a time, in {out}", flush=True)
        wall_s = pop.run_all(out, specs, jobs, int(os.environ.get("COOPNAV_POP_PORT_BASE",
                                                                  "7400")), options.timeout_s)
        (out / "timing.txt").write_text(f"runs {len(specs)} jobs {jobs} wall_s {wall_s:.1f}\n")
    return tabulate(out, args)
