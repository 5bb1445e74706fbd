#!/usr/bin/env bash
# The spoken cue turns a dock into a pass: test/data/scenarios/cue_narrow_responsive
# (a 2.75 m corridor, narrow in the paper's sense of < 3 m, and a responsive person who hears and
# complies) run by scripts/run.sh twice, speaking and with the dialogue manager muted. Muted, the
# person keeps its line and the robot docks at round 2. Speaking, the person hears round 1's
# "I will pass on your right.", keeps to its other side, and the robot passes without docking.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT
scenario="$src/test/data/scenarios/cue_narrow_responsive.yaml"
name=cue_narrow_responsive
# Ports of this test only (its block from COOPNAV_TEST_PORT_BASE, test/CMakeLists.txt).
COOPNAV_RUN_PORT_BASE=$COOPNAV_TEST_PORT_BASE bash "$src/scripts/run.sh" --no-build --out "$tmp/speaking" \
  "$scenario" >"$tmp/speaking.out" 2>&1 ||
  { cat "$tmp/speaking.out"; echo "FAIL: run.sh (speaking)"; exit 1; }
COOPNAV_DAEMON_ARGS_dialogue_manager="--set muted=true" COOPNAV_RUN_PORT_BASE=$((COOPNAV_TEST_PORT_BASE + 10)) \
  bash "$src/scripts/run.sh" --no-build --out "$tmp/muted" "$scenario" >"$tmp/muted.out" 2>&1 ||
  { cat "$tmp/muted.out"; echo "FAIL: run.sh (muted)"; exit 1; }
grep -E "SAY|NOT SAID|ACTION" "$tmp/speaking/$name/transcript.txt" | sed 's/^/speaking: /'
grep -E "SAY|NOT SAID|ACTION" "$tmp/muted/$name/transcript.txt" | sed 's/^/muted:    /'

fail=0
# The words reach the person only when said: heard in the speaking run, never in the muted one.
grep -q "human 1 heard keep_side left at" "$tmp/speaking/$name/world_sim.log" ||
  { echo "FAIL speaking: world_sim did not log the person hearing it should keep left"; fail=1; }
if grep -q "human 1 heard" "$tmp/muted/$name/world_sim.log"; then
  echo "FAIL muted: a person heard a muted robot"; fail=1
fi
grep -q "NOT SAID (muted) INFORM_DIRECTION" "$tmp/muted/$name/transcript.txt" ||
  { echo "FAIL muted: the transcript does not show round 1 as not said (muted)"; fail=1; }

python3 - "$tmp/speaking/summary.json" "$tmp/muted/summary.json" <<'PY' || fail=1
import json, sys
speaking, muted = (json.load(open(p))["scenarios"][0] for p in sys.argv[1:3])
bad = []
for label, s in (("speaking", speaking), ("muted", muted)):
    if s["final_state"] != "GOAL_REACHED" or s["contact"] is not None:
        bad.append(f"{label}: {s['final_state']}, contact {s['contact']} ({s['detail']})")
hs, hm = speaking["humans"][0], muted["humans"][0]
if not hm["docked"]:
    bad.append("muted: the robot did not dock (the words should be what avoids it)")
if hs["docked"]:
    bad.append("speaking: the robot docked although the person kept to the other side")
said = [e for e in hs["transcript"] if e["kind"] == "say" and e["round"] == 1]
if not said or said[0]["act"] != "INFORM_DIRECTION" or said[0]["delivery"] != "said":
    bad.append(f"speaking: round 1 said {said}")
elif not said[0]["lead_s"] > 0.0:
    bad.append(f"speaking: round 1's words end {said[0]['lead_s']} s before the crossing")
if any(e["kind"] == "say" and e["delivery"] != "muted" for e in hm["transcript"]):
    bad.append("muted: an utterance was said")
cs, cm = hs["cm_interaction_m"], hm["cm_interaction_m"]
print(f"CM speaking {cs:.3f} m, muted {cm:.3f} m; time to goal speaking "
      f"{speaking['robot_time_to_goal_s']} s, muted {muted['robot_time_to_goal_s']} s")
if not cs > cm + 0.1:
    bad.append(f"CM speaking {cs} not above muted {cm} + 0.1 m")
for m in bad:
    print("FAIL", m)
sys.exit(1 if bad else 0)
PY
[ "$fail" -eq 0 ] && echo "ok: the spoken cue turns the dock into a pass"
exit "$fail"
