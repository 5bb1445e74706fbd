#!/usr/bin/env bash
# Safe passage end to end, as a user runs it: scripts/run.sh on a 1.8 m corridor with a
# minimally contributing human (test/data/scenarios/corridor_1_8_minimal.yaml). The robot must
# make room that is really room, and the run must end without any contact: no collision, no
# contact in summary.json, and whatever the robot said about making room is what it did.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT
COOPNAV_RUN_PORT_BASE=$COOPNAV_TEST_PORT_BASE bash "$src/scripts/run.sh" --no-build --out "$tmp/run" \
  "$src/test/data/scenarios/corridor_1_8_minimal.yaml" >"$tmp/run.out" 2>&1 ||
  { cat "$tmp/run.out"; echo "FAIL: run.sh"; exit 1; }
cat "$tmp/run/corridor_1_8_minimal/transcript.txt"
python3 - "$tmp/run/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))["scenarios"][0]
bad = []
if s["collision"]:
    bad.append(f"collision: {s['detail']}")
if s.get("contact"):
    bad.append(f"contact: {s['contact']}")
if s.get("outcome") not in (None, "GOAL_REACHED", "STANDSTILL"):
    bad.append(f"outcome {s.get('outcome')}")
print(f"outcome {s.get('outcome')}, min clearance {s.get('min_clearance_m')} m, "
      f"docks {s.get('docks')}, retreats {s.get('retreats')}, guard steps {s.get('guard_steps')}")
for m in bad:
    print("FAIL", m)
sys.exit(1 if bad else 0)
PY
echo "safe passage: 1.8 m corridor with a minimal human ends without contact"
