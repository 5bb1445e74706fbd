#!/usr/bin/env python3
"""Round 2 against what the person did: on a population (scripts/population.sh DIR), for each
head-on person whose round 2 fired, the judgement of cooperation round 2 acted on (the paper's
IsContributing, or p_contributing >= threshold: dialogue_manager `judgement`) beside what the
person did by the crossing.

    tools/exp/round2_agreement.py DIR [DIR ...] [--threshold 0.5]

Per run it reads DIR/population.json (behaviour, role, expected_contributing, contact, time to
goal), DIR/runs/<name>/summary.json (the interaction's CA) and DIR/runs/<name>/dialogue_manager.log
(round 2's first line per human: "round 2 on CM ..., IsContributing X, p_contributing P, ..." and
its branch). Truth, two readings:
  made room  the person's CA at the end of the interaction (the crossing) >= 0.3 m, the forecast's
             own label (lib assessment/forecast.hpp);
  behaviour  population.json's expected_contributing (facilitating and late_facilitating yield,
             minimal and oblivious do not; the others have none).
Decision: round 2's branch "-> ask to move more" (the person is relied on) counts as judged
cooperating, "-> dock" (also the precautionary one) as judged not: the branches that read the
judgement. The others ("!still": the person needs to do no more; repeat Dir with the robot free;
unknowns) decide nothing on the person and are left out of the decision share (they stay in the
judgement share).
Also: the decision share split by whether p_contributing at round 2 was decisive (>= confidence
or <= 1 - confidence, the make-time profile's test) or not; the t_CROSS round 2 decided at
(median; the make-time profile defers it); contacts with the robot at fault and the time-to-goal
ratio against the run without humans (median and 95th percentile).
"""
import argparse
import json
import re
import statistics
import sys
from pathlib import Path

ROUND2 = re.compile(
    r"human (\d+) round 2 on CM (\S+) m against d_h (\S+) m, IsContributing (\w+),"
    r"(?: p_contributing (\S+),)?")
BRANCH = re.compile(r"human (\d+) round 2 \(t_cross ([^)]*)\): (.*)$")
# The make-time profile's wait (daemons/dialogue_manager/README.md "Making time"), before its round 2.
DEFERRED = re.compile(r"human (\d+) round 2 deferred \(t_cross ([^)]*)\)")
MADE_ROOM_M = 0.3


def num(text):
    try:
        return float(text)
    except ValueError:
        return None


def round2_of(log_path):
    """human id -> {is_contributing, p, branch} of its first round 2."""
    out = {}
    deferred = set()
    if not log_path.exists():
        return out
    for line in log_path.read_text(errors="replace").splitlines():
        m = ROUND2.search(line)
        if m:
            hid = int(m.group(1))
            if hid not in out:
                out[hid] = {"is_contributing": m.group(4), "p": num(m.group(5)) if m.group(5) else None, "branch": None}
            continue
        m = BRANCH.search(line)
        if m:
            hid = int(m.group(1))
            if hid in out and out[hid]["branch"] is None:
                out[hid]["branch"] = m.group(3)
                out[hid]["t_cross"] = m.group(2).split()[0]
            continue
        m = DEFERRED.search(line)
        if m:
            deferred.add(int(m.group(1)))
    for hid in deferred:
        if hid in out:
            out[hid]["deferred"] = True
    return out


def decision_of(branch):
    if branch is None:
        return None
    if "-> ask to move more" in branch:
        return True
    if "-> dock" in branch or "precautionary dock" in branch:
        return False
    return None


def judged(r, judgement, threshold):
    if judgement == "cm":
        return {"TRUE": True, "FALSE": False}.get(r["is_contributing"])
    return None if r["p"] is None else r["p"] >= threshold


def share(pairs):
    pairs = [(a, b) for a, b in pairs if a is not None and b is not None]
    if not pairs:
        return "-"
    hit = sum(1 for a, b in pairs if a == b)
    return f"{hit}/{len(pairs)} = {hit / len(pairs):.3f}"


def percentile(values, q):
    """The q-quantile (0..1), linear between order statistics."""
    v = sorted(values)
    if not v:
        return None
    k = (len(v) - 1) * q
    lo = int(k)
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (v[hi] - v[lo]) * (k - lo)


def study(root, threshold):
    pop = json.loads((root / "population.json").read_text())
    rows = []
    contacts_at_fault = 0
    ttg = []
    for run in pop["runs"]:
        if run.get("contact", {}).get("cause") == "robot_at_fault":
            contacts_at_fault += 1
        if run.get("time_to_goal_ratio") is not None:
            ttg.append(run["time_to_goal_ratio"])
        run_dir = root / "runs" / run["name"]
        r2 = round2_of(run_dir / "dialogue_manager.log")
        summary_path = run_dir / "summary.json"
        summary = json.loads(summary_path.read_text()) if summary_path.exists() else None
        for h in run.get("humans", []):
            if h.get("role") != "head_on" or h["id"] not in r2:
                continue
            ca = None
            if summary:
                for s in summary["scenarios"]:
                    for sh in s.get("humans", []):
                        if sh.get("id") == h["id"] and sh.get("ca_m"):
                            ca = sh["ca_m"][-1]
            r = r2[h["id"]]
            t_cross = num(r["t_cross"]) if r.get("t_cross") else None
            rows.append({"run": run["name"], "behaviour": h["behaviour"],
                         "made_room": None if ca is None else ca >= MADE_ROOM_M,
                         "expected": h.get("expected_contributing"),
                         "cm": judged(r, "cm", threshold), "forecast": judged(r, "forecast", threshold),
                         "decision": decision_of(r["branch"]), "branch": r["branch"], "p": r["p"],
                         "t_cross": t_cross, "deferred": r.get("deferred", False)})
    return rows, contacts_at_fault, ttg, len(pop["runs"])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dirs", nargs="+", type=Path)
    ap.add_argument("--threshold", type=float, default=0.5)
    ap.add_argument("--confidence", type=float, default=0.85,
                    help="p_contributing decisive at >= this or <= 1 - this (make_time)")
    ap.add_argument("--rows", action="store_true", help="print every person's row")
    args = ap.parse_args(argv)
    for root in args.dirs:
        rows, at_fault, ttg, n_runs = study(root, args.threshold)
        print(f"== {root}: {n_runs} runs, {len(rows)} head-on people with a round 2")
        if args.rows:
            for r in rows:
                print(f"  {r['run']} {r['behaviour']:17} made_room {r['made_room']} "
                      f"expected {r['expected']} cm {r['cm']} p {r['p']} decision {r['decision']}: "
                      f"{r['branch']}")
        for truth in ("made_room", "expected"):
            print(f"  truth {truth}:")
            print(f"    round-2 decision (ask more vs dock) matches: "
                  f"{share((r['decision'], r[truth]) for r in rows)}")
            print(f"    judgement at round 2, paper IsContributing: "
                  f"{share((r['cm'], r[truth]) for r in rows)}")
            print(f"    judgement at round 2, p_contributing >= {args.threshold}: "
                  f"{share((r['forecast'], r[truth]) for r in rows)}")
            for label, keep in (("decisive", True), ("undecided", False)):
                sub = [r for r in rows if r["p"] is not None and
                       (r["p"] >= args.confidence or r["p"] <= 1 - args.confidence) == keep]
                print(f"    ... with p_contributing {label} at round 2 "
                      f"(confidence {args.confidence}): "
                      f"{share((r['decision'], r[truth]) for r in sub)}")
        waited = [r for r in rows if r["deferred"]]
        if waited:
            decided = [r for r in waited if r["decision"] is not None]
            print(f"  round 2 deferred (make_time): {len(waited)}; then decided ask more / dock "
                  f"{len(decided)} (p decisive {sum(1 for r in decided if r['p'] is not None and (r['p'] >= args.confidence or r['p'] <= 1 - args.confidence))}), "
                  f"no decision on the person {len(waited) - len(decided)}; "
                  f"decisions matching made_room {share((r['decision'], r['made_room']) for r in decided)}")
        t_cross = [r["t_cross"] for r in rows if r["t_cross"] is not None]
        if t_cross:
            print(f"  t_CROSS at round 2: median {statistics.median(t_cross):.2f} s, "
                  f"min {min(t_cross):.2f} s")
        print(f"  contacts with the robot at fault: {at_fault}")
        if ttg:
            print(f"  time to goal / baseline: median {statistics.median(ttg):.3f}, "
                  f"p95 {percentile(ttg, 0.95):.3f}, "
                  f"mean {statistics.fmean(ttg):.3f} over {len(ttg)} runs")
    return 0


if __name__ == "__main__":
    sys.exit(main())
