#!/usr/bin/env bash
# The main job end to end, as a user runs it: scripts/run.sh over the paper's four scenarios
# (real processes, lockstep, LCM logs), twice. Checks the paper's claims on the results
# (CM(facilitating) > tau > CM(minimal) in both corridors, narrow + minimal docks without a
# collision, facilitating humans are thanked, round 1 >= 3 s before crossing and every cue's
# words ended before it), that the two
# runs give identical transcripts and CM values, and that replaying a recorded log into fresh
# assessors and dialogue manager reproduces the recorded transcript.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT
# Ports of this test only (its block from COOPNAV_TEST_PORT_BASE, test/CMakeLists.txt).
COOPNAV_RUN_PORT_BASE=$COOPNAV_TEST_PORT_BASE bash "$src/scripts/run.sh" --no-build --out "$tmp/a" >"$tmp/a.out" 2>&1 ||
  { cat "$tmp/a.out"; echo "FAIL: run.sh (first run)"; exit 1; }
COOPNAV_RUN_PORT_BASE=$((COOPNAV_TEST_PORT_BASE + 10)) bash "$src/scripts/run.sh" --no-build --out "$tmp/b" >"$tmp/b.out" 2>&1 ||
  { cat "$tmp/b.out"; echo "FAIL: run.sh (second run)"; exit 1; }
cat "$tmp/a/cm_table.txt"

fail=0
for s in open_facilitating open_minimal narrow_facilitating narrow_minimal; do
  if ! cmp -s "$tmp/a/$s/transcript.txt" "$tmp/b/$s/transcript.txt"; then
    echo "FAIL $s: transcripts of two runs differ"; diff "$tmp/a/$s/transcript.txt" "$tmp/b/$s/transcript.txt" | head -20
    fail=1
  fi
done

python3 - "$tmp/a/summary.json" "$tmp/b/summary.json" <<'PY' || fail=1
import json, sys
a = {s["scenario"]: s for s in json.load(open(sys.argv[1]))["scenarios"]}
b = {s["scenario"]: s for s in json.load(open(sys.argv[2]))["scenarios"]}
bad = []
def human(s):
    hs = s["humans"]
    assert len(hs) == 1, f"{s['scenario']}: expected one human, got {len(hs)}"
    return hs[0]
for corridor in ("open", "narrow"):
    fac, mini = human(a[corridor + "_facilitating"]), human(a[corridor + "_minimal"])
    cf, cmn, tau = fac["cm_interaction_m"], mini["cm_interaction_m"], fac["tau_m"]
    print(f"{corridor}: CM facilitating {cf}, minimal {cmn}, tau {tau}")
    if cf is None or cmn is None or not (cf > tau > cmn):
        bad.append(f"{corridor}: want CM(facilitating) > tau > CM(minimal), got {cf}, {tau}, {cmn}")
    if not fac["thanked"]:
        bad.append(f"{corridor}_facilitating: the facilitating human was not thanked")
nm = a["narrow_minimal"]
if not human(nm)["docked"]:
    bad.append("narrow_minimal: the robot did not dock")
for name, s in a.items():
    if s["collision"]:
        bad.append(f"{name}: collision ({s['detail']})")
    for h in s["humans"]:
        for e in h["transcript"]:
            if (e.get("kind", "say") == "say" and e.get("round") in (1, 2)
                    and e.get("delivery", "said") == "said"):
                # Round 1 early enough to be acted on; every said cue's words end before the
                # crossing (round 2 may wait for the response to round 1 until t_CROSS 3 s).
                if e["round"] == 1 and (e["t_cross_s"] is None or e["t_cross_s"] < 3.0):
                    bad.append(f"{name}: round 1 at t={e['t_s']} given {e['t_cross_s']} s before crossing")
                if not (e.get("lead_s") is not None and e["lead_s"] > 0.0):
                    bad.append(f"{name}: cue at t={e['t_s']} ends {e.get('lead_s')} s before crossing")
    for ha, hb in zip(s["humans"], b[name]["humans"]):
        for key in ("cm_interaction_m", "cm_window_m", "docked", "thanked"):
            if ha[key] != hb[key]:
                bad.append(f"{name}: {key} differs between runs: {ha[key]} vs {hb[key]}")
for m in bad:
    print("FAIL", m)
sys.exit(1 if bad else 0)
PY

# Replay: the recorded world into fresh assessors + dialogue manager gives the same transcript.
COOPNAV_REPLAY_PORT=$((COOPNAV_TEST_PORT_BASE + 20)) bash "$src/scripts/replay.sh" --no-build --speed 1 --out-dir "$tmp/replay" \
  "$tmp/a/narrow_minimal/narrow_minimal.lcm" >"$tmp/replay.txt" 2>"$tmp/replay.err" ||
  { cat "$tmp/replay.err"; echo "FAIL: replay.sh"; fail=1; }
if ! cmp -s "$tmp/replay.txt" "$tmp/a/narrow_minimal/transcript.txt"; then
  echo "FAIL: replayed transcript differs from the recorded one"
  diff "$tmp/a/narrow_minimal/transcript.txt" "$tmp/replay.txt" | head -30
  fail=1
fi
[ "$fail" -eq 0 ] && echo "paper scenarios: all checks pass"
exit "$fail"
