"""The field's metrics of a population with 95 % intervals (docs/metrics.md).

`scripts/coopnav metrics DIR... [--out PREFIX]` reads every run's metrics JSON under the
directories (`coopnav_ctl metrics` output, format coopnav-metrics/1); a run log (`*.lcm`) without
one beside it (`<log stem>.metrics.json`, or the `metrics.json` every run writes beside its
summary.json) is scored first with `coopnav_ctl metrics`, with the
run's scenario file as its map when the population holds it (`DIR/scenarios/<name>.yaml`).
It writes PREFIX.txt (the table, also printed), PREFIX.csv and PREFIX.json: per metric the
estimate and its interval (Wilson for proportions, percentile bootstrap with a fixed seed for
means), then per person Responsibility and Engagement next to the path assessor's CM, and how
well they agree (Spearman's ρ of the person's responsibility share against CM, and the AUC of that
share for the assessor's "contributing" verdict), each with a bootstrap interval, also drawn in
PREFIX_agreement.png and .svg (each share against CM per person, the ROC of the share for the
verdict; --no-figures: none).
Robot-alone baseline runs (`base_*`) are left out unless --include-baselines.

With --paired each DIR is a variant of the same encounters (an ablation: the same scenarios run
with another profile or without assessment): the table gets, for every variant against the first
DIR, per metric the mean difference over the encounters both ran (paired bootstrap interval) and
its p-value (exact McNemar for rates, Wilcoxon signed-rank otherwise); runs are matched by
scenario name, persons by scenario and id.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import os
import subprocess
import sys
from pathlib import Path
from typing import Iterable

from . import stats

METRICS_FORMAT = "coopnav-metrics/1"
RUN_METRICS_FILE = "metrics.json"  # what every run writes beside its summary.json (run.run_one)

# (key, kind, label): "rate" = a proportion of runs (Wilson), "mean" = a mean (bootstrap).
RUN_METRICS: list[tuple[str, str, str]] = [
    ("success", "rate", "success"),
    ("collision", "rate", "collision"),
    ("timeout", "rate", "timeout"),
    ("failure_to_progress", "rate", "failure to progress"),
    ("robot_on_person_collisions", "mean", "robot-on-person collisions / run"),
    ("person_on_robot_collisions", "mean", "person-on-robot collisions / run"),
    ("wall_collisions", "mean", "wall collisions / run"),
    ("time_to_goal_s", "mean", "time to goal [s]"),
    ("stalled_s", "mean", "stalled time [s]"),
    ("longest_no_progress_s", "mean", "longest span without progress [s]"),
    ("path_length_m", "mean", "path length [m]"),
    ("path_length_ratio", "mean", "path length ratio"),
    ("spl", "mean", "SPL"),
    ("cumulative_heading_change_rad", "mean", "cumulative heading change [rad]"),
    ("path_irregularity_rad", "mean", "path irregularity [rad]"),
    ("path_irregularity_rad_per_m", "mean", "path irregularity [rad/m]"),
    ("goal_traversal_ratio", "mean", "goal traversal ratio (final / initial distance)"),
    ("avg_speed_m_s", "mean", "avg speed [m/s]"),
    ("max_speed_m_s", "mean", "max speed [m/s]"),
    ("avg_acceleration_m_s2", "mean", "avg acceleration [m/s2]"),
    ("max_acceleration_m_s2", "mean", "max acceleration [m/s2]"),
    ("avg_jerk_m_s3", "mean", "avg jerk [m/s3]"),
    ("max_jerk_m_s3", "mean", "max jerk [m/s3]"),
    ("motion_energy_m2_s", "mean", "motion energy [m2/s]"),
    ("min_clearing_distance_m", "mean", "min clearing distance [m]"),
    ("space_compliance", "mean", "space compliance (share < 0.5 m)"),
    ("min_distance_to_person_m", "mean", "min distance to a person [m]"),
    ("avg_closest_person_distance_m", "mean", "avg distance to the closest person [m]"),
    ("min_ttc_s", "mean", "min time to collision [s]"),
    ("intimate_share", "mean", "intimate zone share (< 0.45 m)"),
    ("personal_share", "mean", "personal zone share (0.45-1.2 m)"),
    ("social_share", "mean", "social zone share (1.2-3.6 m)"),
    ("intimate_s", "mean", "time in the intimate zone [s]"),
    ("personal_s", "mean", "time in the personal zone [s]"),
    ("discomfort_frequency", "mean", "discomfort frequency (< 0.2 m)"),
    ("personal_space_cost_s", "mean", "personal-space cost [s]"),
    ("social_work", "mean", "social work [m/s]"),
    ("obstacle_work", "mean", "obstacle part of social work [m/s]"),
]

PERSON_METRICS: list[tuple[str, str]] = [
    ("robot_responsibility", "robot's Responsibility share"),
    ("person_responsibility", "person's Responsibility share"),
    ("robot_engagement", "robot's Engagement share"),
    ("person_engagement", "person's Engagement share"),
    ("max_conflict_intensity", "max conflict intensity"),
    ("cm_interaction_m", "CM, interaction [m]"),
    ("p_contributing", "p_contributing (forecast)"),
]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("dirs", nargs="+", type=Path,
                        help="population directories (or run directories, or metrics JSON files)")
    parser.add_argument("--out", type=Path, default=None,
                        help="output prefix (default: DIR/metrics_table for the first DIR)")
    parser.add_argument("--ctl", type=Path, default=None,
                        help="coopnav_ctl (default: $COOPNAV_BUILD_DIR/tools/coopnav_ctl)")
    parser.add_argument("--rescore", action="store_true",
                        help="score every log again, even where a metrics JSON exists")
    parser.add_argument("--include-baselines", action="store_true",
                        help="keep the robot-alone baseline runs (base_*) in the table")
    parser.add_argument("--paired", action="store_true",
                        help="each DIR is a variant of the same encounters: paired comparisons "
                             "of every variant against the first")
    parser.add_argument("--no-figures", dest="figures", action="store_false",
                        help="no PREFIX_agreement figure (Responsibility and Engagement vs CM)")
    parser.add_argument("--seed", type=int, default=stats.DEFAULT_SEED,
                        help="bootstrap seed (default %(default)s)")
    parser.add_argument("--n-boot", type=int, default=stats.DEFAULT_N_BOOT,
                        help="bootstrap resamples (default %(default)s)")


def default_ctl() -> Path:
    build = Path(os.environ.get("COOPNAV_BUILD_DIR", "build"))
    return build / "tools" / "coopnav_ctl"


def _scenario_file(log: Path) -> Path | None:
    """DIR/scenarios/<name>.yaml of a population run DIR/runs/<name>/<name>.lcm."""
    candidate = log.parent.parent.parent / "scenarios" / (log.stem + ".yaml")
    return candidate if candidate.is_file() else None


def score_log(log: Path, ctl: Path) -> Path:
    """Runs coopnav_ctl metrics on one log; returns the JSON written beside it."""
    out = log.with_name(log.stem + ".metrics.json")
    cmd = [str(ctl), "metrics", str(log), "--json", str(out)]
    scenario = _scenario_file(log)
    if scenario is not None:
        cmd += ["--map", str(scenario)]
    done = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if done.returncode != 0 or not out.is_file():
        raise RuntimeError(f"{' '.join(cmd)} failed ({done.returncode}): {done.stderr.strip()}")
    return out


def find_metrics(paths: Iterable[Path], ctl: Path, rescore: bool = False,
                 unscored: list[str] | None = None) -> list[Path]:
    """Every metrics JSON under the paths, scoring logs that have none. A log that cannot be
    scored (empty, no agent states) is reported in `unscored` ("log: why") when given, else
    raises RuntimeError."""
    found: list[Path] = []

    def score(log: Path) -> Path | None:
        try:
            return score_log(log, ctl)
        except RuntimeError as e:
            if unscored is None:
                raise
            unscored.append(str(e))
            return None

    for root in paths:
        if root.is_file():
            scored = score(root) if root.suffix == ".lcm" else root
            if scored is not None:
                found.append(scored)
            continue
        if not root.is_dir():
            raise FileNotFoundError(f"{root}: no such file or directory")
        jsons = {p for p in root.rglob("*.metrics.json")}
        for log in sorted(root.rglob("*.lcm")):
            beside = log.with_name(log.stem + ".metrics.json")
            # run_one's own: DIR/metrics.json beside the run's summary.json and log.
            own = log.with_name(RUN_METRICS_FILE)
            if not rescore and beside not in jsons and own.is_file():
                jsons.add(own)
                continue
            if rescore or beside not in jsons:
                jsons.discard(beside)  # a stale file of a log that no longer scores is not kept
                if score(log) is not None:
                    jsons.add(beside)
        found.extend(sorted(jsons))
    return found


def load_runs(files: Iterable[Path]) -> list[dict]:
    """The runs of metrics JSON files (format checked), in file order."""
    runs: list[dict] = []
    for f in files:
        with open(f, encoding="utf-8") as fh:
            doc = json.load(fh)
        if not isinstance(doc, dict) or doc.get("format") != METRICS_FORMAT:
            raise ValueError(f"{f}: not a {METRICS_FORMAT} file")
        runs.extend(doc.get("runs", []))
    return runs


def _finite(values: Iterable) -> list[float]:
    out = []
    for v in values:
        if v is None:
            continue
        v = float(v)
        if math.isfinite(v):
            out.append(v)
    return out


def aggregate(runs: list[dict], *, seed: int = stats.DEFAULT_SEED,
              n_boot: int = stats.DEFAULT_N_BOOT) -> dict:
    """The table as a dict: runs, per-run metrics, per-person metrics, agreement with CM."""
    table: dict = {"format": "coopnav-metrics-table/1", "runs": len(runs), "seed": seed,
                   "n_boot": n_boot, "metrics": [], "persons": [], "agreement": []}
    for key, kind, label in RUN_METRICS:
        values = [r.get(key) for r in runs]
        if kind == "rate":
            known = [bool(v) for v in values if v is not None]
            iv = stats.wilson(sum(known), len(known))
            method = "wilson"
        else:
            iv = stats.bootstrap(_finite(values), n_boot=n_boot, seed=seed)
            method = "bootstrap-mean"
        table["metrics"].append({"key": key, "label": label, "method": method, **iv.as_dict()})
    persons = [p for r in runs for p in r.get("persons", [])]
    table["person_count"] = len(persons)
    for key, label in PERSON_METRICS:
        iv = stats.bootstrap(_finite(p.get(key) for p in persons), n_boot=n_boot, seed=seed)
        table["persons"].append({"key": key, "label": label, "method": "bootstrap-mean",
                                 **iv.as_dict()})
    # Agreement of the outside measure with CM: a person who took a larger share of resolving
    # the conflict should have a larger CM (moved further off its path on its own side).
    for share in ("person_responsibility", "person_engagement"):
        x, y = stats.finite_pairs([p.get(share) for p in persons],
                                  [p.get("cm_interaction_m") for p in persons])
        rho = stats.bootstrap_spearman(x, y, n_boot=n_boot, seed=seed)
        table["agreement"].append({"key": f"spearman({share}, cm_interaction_m)",
                                   "label": f"Spearman rho, {share.replace('_', ' ')} vs CM",
                                   "method": "bootstrap-spearman", **rho.as_dict()})
        scores, labels = [], []
        for p in persons:
            s, verdict = p.get(share), p.get("is_contributing_interaction")
            if s is None or verdict is None or not math.isfinite(float(s)):
                continue
            scores.append(float(s))
            labels.append(bool(verdict))
        a = stats.bootstrap_auc(scores, labels, n_boot=n_boot, seed=seed)
        table["agreement"].append({"key": f"auc({share}, is_contributing_interaction)",
                                   "label": f"AUC, {share.replace('_', ' ')} for CM's verdict",
                                   "method": "bootstrap-auc-stratified", **a.as_dict()})
    return table


def agreement_points(runs: list[dict], share: str = "person_responsibility"
                     ) -> tuple[list[float], list[float], list[bool | None]]:
    """Per person crossed with both a finite `share` and a finite CM: the share, the CM and the
    assessor's verdict (is_contributing_interaction; None when it gave none)."""
    xs, ys, verdicts = [], [], []
    for r in runs:
        for p in r.get("persons", []):
            x, y = p.get(share), p.get("cm_interaction_m")
            if x is None or y is None or not (math.isfinite(float(x)) and math.isfinite(float(y))):
                continue
            xs.append(float(x))
            ys.append(float(y))
            v = p.get("is_contributing_interaction")
            verdicts.append(None if v is None else bool(v))
    return xs, ys, verdicts


def roc_points(scores: list[float], labels: list[bool]) -> tuple[list[float], list[float]]:
    """The ROC curve of `scores` for `labels` (false and true positive rates, from (0, 0) to
    (1, 1)), every distinct score a threshold: its area is stats.auc's."""
    pos = sum(labels)
    neg = len(labels) - pos
    if pos == 0 or neg == 0:
        return [], []
    fpr, tpr = [0.0], [0.0]
    tp = fp = 0
    order = sorted(range(len(scores)), key=lambda i: -scores[i])
    i = 0
    while i < len(order):
        j = i
        while j < len(order) and scores[order[j]] == scores[order[i]]:
            tp += labels[order[j]]
            fp += not labels[order[j]]
            j += 1
        fpr.append(fp / neg)
        tpr.append(tp / pos)
        i = j
    return fpr, tpr


def agreement_figure(runs: list[dict], stem: Path, *, title: str = "",
                     seed: int = stats.DEFAULT_SEED, n_boot: int = stats.DEFAULT_N_BOOT
                     ) -> list[Path]:
    """How well the outside measure agrees with CM (Honda Research Institute's Responsibility
    and Engagement against the path assessor's CM), PNG and SVG at `stem`: each share against
    CM per person (colour: the assessor's verdict) with Spearman's rho and its interval, and the
    ROC of the Responsibility share for the verdict with its AUC. Nothing (an empty list) when no
    person has both a share and a CM (e.g. a run without the path assessor)."""
    resp = agreement_points(runs, "person_responsibility")
    eng = agreement_points(runs, "person_engagement")
    if not resp[0] and not eng[0]:
        return []
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .figures import save

    colours = {True: "#2ca02c", False: "#d62728", None: "#7f7f7f"}
    names = {True: "contributing", False: "not contributing", None: "no verdict"}
    fig, axes = plt.subplots(1, 3, figsize=(13.5, 4.2))
    for ax, (xs, ys, verdicts), what in ((axes[0], resp, "Responsibility"),
                                         (axes[1], eng, "Engagement")):
        for v in (True, False, None):
            pts = [(x, y) for x, y, w in zip(xs, ys, verdicts) if w is v]
            if pts:
                ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=14, alpha=0.7,
                           color=colours[v], label=f"{names[v]} ({len(pts)})")
        rho = stats.bootstrap_spearman(xs, ys, n_boot=n_boot, seed=seed)
        ax.set_title(f"person's {what} share vs CM\nSpearman rho {_fmt(_num(rho.value))} "
                     f"[{_fmt(_num(rho.lo))}, {_fmt(_num(rho.hi))}], n {rho.n}", fontsize=8)
        ax.set_xlabel(f"person's {what} share (of resolving the conflict)", fontsize=8)
        ax.set_ylabel("CM over the interaction [m]", fontsize=8)
        ax.grid(alpha=0.3)
        if xs:
            ax.legend(fontsize=7)
    scores = [x for x, v in zip(resp[0], resp[2]) if v is not None]
    labels = [bool(v) for v in resp[2] if v is not None]
    ax = axes[2]
    fpr, tpr = roc_points(scores, labels)
    a = stats.bootstrap_auc(scores, labels, n_boot=n_boot, seed=seed)
    if fpr:
        ax.plot(fpr, tpr, color="#1f77b4")  # straight between thresholds: area = AUC
    ax.plot([0, 1], [0, 1], color="#7f7f7f", lw=0.8, ls="--")
    ax.set_title(f"Responsibility share for CM's verdict\nAUC {_fmt(_num(a.value))} "
                 f"[{_fmt(_num(a.lo))}, {_fmt(_num(a.hi))}], n {a.n}", fontsize=8)
    ax.set_xlabel("false positive rate", fontsize=8)
    ax.set_ylabel("true positive rate", fontsize=8)
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    written = save(fig, Path(stem))
    plt.close(fig)
    return written


def _num(v: float | None) -> float | None:
    return None if v is None or not math.isfinite(v) else v


def _as_float(v) -> float:
    return math.nan if v is None else float(v)


def paired_table(variants: dict[str, list[dict]], *, seed: int = stats.DEFAULT_SEED,
                 n_boot: int = stats.DEFAULT_N_BOOT) -> list[dict]:
    """Every variant against the first (the reference) on the encounters both ran."""
    names = list(variants)
    reference = names[0]
    by_name = {v: {r.get("scenario"): r for r in runs} for v, runs in variants.items()}

    def persons_of(v: str) -> dict:
        return {(r.get("scenario"), p.get("id")): p for r in variants[v]
                for p in r.get("persons", [])}

    rows: list[dict] = []
    ref_persons = persons_of(reference)
    for other in names[1:]:
        common = [s for s in by_name[reference] if s in by_name[other]]
        for key, kind, label in RUN_METRICS:
            a, b = [], []
            for scenario in common:
                x, y = by_name[reference][scenario].get(key), by_name[other][scenario].get(key)
                if x is None or y is None:
                    continue
                a.append(_as_float(x))
                b.append(_as_float(y))
            a, b = stats.finite_pairs(a, b)
            rows.append(_paired_row(reference, other, key, label, kind == "rate", a, b, seed,
                                    n_boot))
        other_persons = persons_of(other)
        both = [k for k in ref_persons if k in other_persons]
        for key, label in PERSON_METRICS:
            a, b = stats.finite_pairs([ref_persons[k].get(key) for k in both],
                                      [other_persons[k].get(key) for k in both])
            rows.append(_paired_row(reference, other, key, label, False, a, b, seed, n_boot))
    return rows


def _paired_row(reference: str, other: str, key: str, label: str, binary: bool, a: list,
                b: list, seed: int, n_boot: int) -> dict:
    row = {"reference": reference, "variant": other, "key": key, "label": label,
           "n_pairs": len(a), "reference_mean": None, "variant_mean": None,
           "difference": None, "lo": None, "hi": None, "p_value": None, "test": None}
    if not a:
        return row
    r = stats.paired_compare(a, b, binary=binary, n_boot=n_boot, seed=seed)
    row.update({"reference_mean": sum(a) / len(a), "variant_mean": sum(b) / len(b),
                "difference": r.mean_difference.value, "lo": r.mean_difference.lo,
                "hi": r.mean_difference.hi, "p_value": r.p_value, "test": r.test})
    return row


def format_paired(rows: list[dict]) -> str:
    if not rows:
        return ""
    width = max(len(r["label"]) for r in rows)
    lines = []
    for variant in dict.fromkeys(r["variant"] for r in rows):
        ref = rows[0]["reference"]
        lines.append(f"\n## paired: {variant} - {ref} (same encounters)")
        lines.append(f"{'metric':<{width}}  {ref[:9]:>9}  {variant[:9]:>9}  {'difference':>10}  "
                     f"{'95 % interval':>19}  {'p':>7}  {'pairs':>5}")
        for r in rows:
            if r["variant"] != variant:
                continue
            interval = f"[{_fmt(r['lo'])}, {_fmt(r['hi'])}]"
            p = "-" if r["p_value"] is None else f"{r['p_value']:.4f}"
            lines.append(f"{r['label']:<{width}}  {_fmt(r['reference_mean']):>9}  "
                         f"{_fmt(r['variant_mean']):>9}  {_fmt(r['difference']):>10}  "
                         f"{interval:>19}  {p:>7}  {r['n_pairs']:>5}")
    return "\n".join(lines) + "\n"


def _fmt(v: float | None) -> str:
    if v is None:
        return "-"
    return f"{v:.3f}" if abs(v) < 1000 else f"{v:.1f}"


def format_table(table: dict) -> str:
    lines = [f"# {table['runs']} runs, {table['person_count']} persons; 95 % intervals "
             f"(Wilson for rates, percentile bootstrap seed {table['seed']}, "
             f"{table['n_boot']} resamples)"]
    width = max(len(row["label"]) for part in ("metrics", "persons", "agreement")
                for row in table[part])
    for title, part in (("run", "metrics"), ("per person", "persons"),
                        ("agreement with CM", "agreement")):
        lines.append(f"\n## {title}")
        lines.append(f"{'metric':<{width}}  {'value':>9}  {'95 % interval':>19}  {'n':>5}")
        for row in table[part]:
            interval = f"[{_fmt(row['lo'])}, {_fmt(row['hi'])}]"
            lines.append(f"{row['label']:<{width}}  {_fmt(row['value']):>9}  {interval:>19}  "
                         f"{row['n']:>5}")
    return "\n".join(lines) + "\n"


def table_csv(table: dict) -> str:
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["part", "key", "label", "method", "value", "lo", "hi", "n"])
    for part in ("metrics", "persons", "agreement"):
        for row in table[part]:
            w.writerow([part, row["key"], row["label"], row["method"],
                        "" if row["value"] is None else repr(row["value"]),
                        "" if row["lo"] is None else repr(row["lo"]),
                        "" if row["hi"] is None else repr(row["hi"]), row["n"]])
    for row in table.get("paired", []):
        # value: the mean difference variant - reference; method: the test and its p-value.
        w.writerow([f"paired:{row['variant']}-{row['reference']}", row["key"], row["label"],
                    "" if row["test"] is None else f"{row['test']} p={row['p_value']!r}",
                    "" if row["difference"] is None else repr(row["difference"]),
                    "" if row["lo"] is None else repr(row["lo"]),
                    "" if row["hi"] is None else repr(row["hi"]), row["n_pairs"]])
    return out.getvalue()


def main(args: argparse.Namespace) -> int:
    ctl = args.ctl or default_ctl()
    unscored: list[str] = []
    try:
        files = find_metrics(args.dirs, ctl, rescore=args.rescore, unscored=unscored)
        runs = load_runs(files)
    except (OSError, RuntimeError, ValueError, json.JSONDecodeError) as e:
        print(f"coopnav metrics: {e}", file=sys.stderr)
        return 2
    if not args.include_baselines:
        runs = [r for r in runs if not str(r.get("scenario", "")).startswith("base_")]
    if not runs:
        print("coopnav metrics: no runs found", file=sys.stderr)
        return 2
    if not args.paired:
        table = aggregate(runs, seed=args.seed, n_boot=args.n_boot)
        text = format_table(table)
    else:
        # One table per variant (the first DIR's is the table's own), then the paired rows.
        if len(args.dirs) < 2:
            print("coopnav metrics: --paired needs two or more variant directories",
                  file=sys.stderr)
            return 2
        variants: dict[str, list[dict]] = {}
        for d in args.dirs:
            name = d.name if d.name not in variants else str(d)
            vruns = load_runs(find_metrics([d], ctl, unscored=[]))  # reported above
            variants[name] = [r for r in vruns if args.include_baselines
                              or not str(r.get("scenario", "")).startswith("base_")]
        tables = {name: aggregate(vruns, seed=args.seed, n_boot=args.n_boot)
                  for name, vruns in variants.items() if vruns}
        names = list(variants)
        if names[0] not in tables:
            print(f"coopnav metrics: no runs in {args.dirs[0]}", file=sys.stderr)
            return 2
        table = tables[names[0]]
        table["variant"] = names[0]
        table["variant_tables"] = {n: t for n, t in tables.items() if n != names[0]}
        text = "".join(f"# variant {n}\n" + format_table(t) + "\n" for n, t in tables.items())
        table["paired"] = paired_table(variants, seed=args.seed, n_boot=args.n_boot)
        text += format_paired(table["paired"])
    for why in unscored:
        print(f"coopnav metrics: not scored: {why}", file=sys.stderr)
    table["unscored"] = unscored
    if unscored:
        text = f"# {len(unscored)} logs could not be scored (stderr; the JSON's unscored)\n" + text
    first = args.dirs[0]
    prefix = args.out or ((first if first.is_dir() else first.parent) / "metrics_table")
    Path(f"{prefix}.txt").write_text(text, encoding="utf-8")
    Path(f"{prefix}.csv").write_text(table_csv(table), encoding="utf-8")
    Path(f"{prefix}.json").write_text(json.dumps(table, indent=2) + "\n", encoding="utf-8")
    sys.stdout.write(text)
    if args.figures:
        shown = runs if not args.paired else variants[names[0]]
        drawn = agreement_figure(shown, Path(f"{prefix}_agreement"), seed=args.seed,
                                 n_boot=args.n_boot, title=f"{len(shown)} runs")
        if drawn:
            print(f"coopnav metrics: {drawn[0]} (Responsibility and Engagement against CM)",
                  file=sys.stderr)
    return 0
