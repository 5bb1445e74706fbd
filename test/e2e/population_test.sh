#!/usr/bin/env bash
# The population tool end to end, as a user runs it: scripts/population.sh over 20 generated
# encounters (fixed seed, 2 at a time, real processes in lockstep). Fails when any contact has the
# robot at fault (or cannot be cleared of it), when a run fails a dialogue check, when a run
# leaves no summary, when population.json does not read back consistent with the plan and the
# table, or when the same seed does not give the same scenario files byte for byte. Then a small
# crowd population (--crowd: flows both ways, a group abreast, people standing talking, a
# junction) held to the same, with the crowd checks of every run (summary.json dialogue_checks:
# nothing said to someone not being crossed, no contradiction, no group told twice, every
# sentence addressed among several people) and a progress line per run.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
pop="$COOPNAV_BUILD_DIR/tools/population/coopnav_population"
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT

start_s=$(date +%s)
rc=0
# Ports of this test only (its block from COOPNAV_TEST_PORT_BASE, test/CMakeLists.txt).
COOPNAV_POP_PORT_BASE=$COOPNAV_TEST_PORT_BASE bash "$src/scripts/population.sh" --no-build --n 20 --seed 29 -j 2 \
  --out "$tmp/p" >"$tmp/out" 2>&1 || rc=$?
echo "population of 20 (+ runs without humans) in $(($(date +%s) - start_s)) s wall"
fail=0
case "$rc" in
  0) ;;
  1) echo "FAIL: a contact with the robot at fault (or unattributed)"; fail=1 ;;
  4) echo "FAIL: a run failed a dialogue check"; fail=1 ;;
  # 5: a run ended in a contact (a human walking into the robot too), a standstill, the time limit
  # or a mutual wait over 10 s. A stalemate fails; an oblivious walker walking into the robot
  # (human_walked_in: the robot at rest or moving away) is reported, not failed, since this
  # seed's 20 have two of them (issue 44).
  5) grep -A20 'ended in a contact' "$tmp/out" || true
     reasons="$(grep -A20 'ended in a contact' "$tmp/out" | grep -E '^  pop_[0-9]+: ' || true)"
     if [ -z "$reasons" ] || grep -vqE ': contact \(human_walked_in\)$' <<<"$reasons"; then
       echo "FAIL: a run ended in a standstill, the time limit, a long mutual wait or a contact other than a human walking in"
       fail=1
     else
       echo "WARN: a human walked into the robot"
     fi ;;
  3) echo "FAIL: runs without a summary (see $tmp/p/runs/*/world_sim.log)"; fail=1 ;;
  *) cat "$tmp/out"; echo "FAIL: population.sh exited $rc"; exit 1 ;;
esac
cat "$tmp/p/population.txt"

"$pop" check --dir "$tmp/p" || { echo "FAIL: population.json is not well formed"; fail=1; }
grep -q '"robot_at_fault_or_unattributed": 0,' "$tmp/p/population.json" ||
  { echo "FAIL: population.json counts robot-at-fault contacts"; fail=1; }
if [ "$(grep -c '^pop_00[0-9][0-9] ' "$tmp/p/population.txt")" -ne 20 ]; then
  echo "FAIL: the table does not have one line per run"
  fail=1
fi

"$pop" generate --n 20 --seed 29 --out "$tmp/q" --maps-dir "$src/config/maps" >/dev/null
if ! diff -r "$tmp/p/scenarios" "$tmp/q/scenarios" >/dev/null ||
  ! cmp -s "$tmp/p/plan.json" "$tmp/q/plan.json"; then
  echo "FAIL: the same seed gave other scenario files"
  fail=1
fi
"$pop" generate --n 20 --seed 30 --out "$tmp/r" --maps-dir "$src/config/maps" >/dev/null
if diff -r "$tmp/p/scenarios" "$tmp/r/scenarios" >/dev/null; then
  echo "FAIL: another seed gave the same scenario files"
  fail=1
fi

# Crowds: 6 encounters (every kind at least once) and their runs without humans, on ports of
# their own.
start_s=$(date +%s)
rc=0
COOPNAV_POP_PORT_BASE=$((COOPNAV_TEST_PORT_BASE + 100)) bash "$src/scripts/population.sh" --no-build \
  --crowd --n 6 --seed 3 -j 2 --out "$tmp/c" >"$tmp/cout" 2>&1 || rc=$?
echo "crowd population of 6 (+ runs without humans) in $(($(date +%s) - start_s)) s wall"
case "$rc" in
  0) ;;
  1) echo "FAIL: crowds: a contact with the robot at fault (or unattributed)"; fail=1 ;;
  4) echo "FAIL: crowds: a run failed a dialogue check (see the words column)"; fail=1 ;;
  5) grep -A20 'ended in a contact' "$tmp/cout" || true
     echo "WARN: crowds: a run ended in a contact, a standstill, the time limit or a long mutual wait" ;;
  3) echo "FAIL: crowds: runs without a summary (see $tmp/c/runs/*/world_sim.log)"; fail=1 ;;
  *) cat "$tmp/cout"; echo "FAIL: population.sh --crowd exited $rc"; exit 1 ;;
esac
cat "$tmp/c/population.txt"
"$pop" check --dir "$tmp/c" || { echo "FAIL: crowd population.json is not well formed"; fail=1; }
python3 - "$tmp/c/population.json" <<'PY' || fail=1
import json, sys
t = json.load(open(sys.argv[1]))["totals"]
d = t["dialogue_checks"]
bad = []
if t["robot_at_fault_or_unattributed"]:
    bad.append(f"{t['robot_at_fault_or_unattributed']} contact(s) with the robot at fault")
if d["runs_checked"] != t["runs"]:
    bad.append(f"dialogue checks of {d['runs_checked']} of {t['runs']} runs")
for k in ("runs_said_to_not_crossing", "runs_contradictions", "runs_told_twice",
          "runs_unaddressed_with_several", "failing_runs"):
    if d[k]:
        bad.append(f"dialogue_checks.{k} = {d[k]}")
if sorted(t["by_kind"]) != ["flows", "group_abreast", "junction", "standing_talk"]:
    bad.append(f"crowd kinds {sorted(t['by_kind'])}")
for m in bad:
    print("FAIL: crowds:", m)
sys.exit(1 if bad else 0)
PY
# Piped, the progress is one plain line per finished run: "[k/n] name state sim .. wall .. ETA".
runs="$(grep -c '' "$tmp/c/jobs.txt")"
if [ "$(grep -cE "^\[[0-9]+/$runs\] [a-z_0-9]+ +[A-Z_]+ +sim .* ETA [0-9]+m[0-9]{2}s$" "$tmp/cout")" -ne "$runs" ] ||
  grep -q $'\r' "$tmp/cout"; then
  echo "FAIL: not one progress line per run:"
  grep '^\[' "$tmp/cout" || true
  fail=1
fi
"$pop" generate --crowd --n 6 --seed 3 --out "$tmp/cq" --maps-dir "$src/config/maps" >/dev/null
if ! diff -r "$tmp/c/scenarios" "$tmp/cq/scenarios" >/dev/null ||
  ! cmp -s "$tmp/c/plan.json" "$tmp/cq/plan.json"; then
  echo "FAIL: the same crowd seed gave other scenario files"
  fail=1
fi

[ "$fail" -eq 0 ] && echo "PASS"
exit "$fail"
