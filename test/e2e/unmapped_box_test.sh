#!/usr/bin/env bash
# A guard that sees what the map does not (issue 45), end to end through scripts/run.sh: a box
# stands in open.pgm's 2.25 m corridor, in the robot's way, and is not on the robot's map; only
# world_sim's simulated laser (COOPNAV_SCAN) shows it to the band source.
#  1. unmapped_box_corridor, the box alone, 1.4 m free beside it: the robot's global path, planned
#     again round the laser's returns, goes round the box; it reaches its goal (run.sh exit 0)
#     with no collision and a clearance > 0 from the box.
#  2. unmapped_box_blocked, a box leaving 0.7 m for the 0.94 m robot: no room beside it; the robot
#     turns back well before it (clearance > 1 m) for open.pgm's parallel corridor, the way round,
#     and never squeezes towards the gap; the run ends at its time limit (run.sh exit 3) on the way.
#  3. unmapped_box_encounter, the box where the robot meets a minimal human whose lane is the way
#     round: no collision, no contact with the human, clearance > 0 from the box, and both reach
#     their goals (exit 0).
#  4. The control: the first scenario with the laser off (world_sim --set laser=off): the robot,
#     blind to the box, drives into it (the run ends in COLLISION). So the first run's clearance
#     is the scan's doing.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT
scen="$src/test/data/scenarios"
port=$COOPNAV_TEST_PORT_BASE

run() {  # run NAME OUT EXPECTED_RC [world_sim args]
  # run.sh exits 3 when a run ends in a contact, a standstill or the time limit: the box with no
  # room beside it (the time limit, on the way round) and the blind control (a collision) expect it.
  local name=$1 out=$2 expected=$3 rc=0
  COOPNAV_RUN_PORT_BASE=$port COOPNAV_DAEMON_ARGS_world_sim="${4:-}" bash "$src/scripts/run.sh" \
    --no-build --out "$out" "$scen/$name.yaml" >"$out.out" 2>&1 || rc=$?
  if [ "$rc" != "$expected" ]; then
    cat "$out.out"
    echo "FAIL: run.sh $name exited $rc, expected $expected"
    exit 1
  fi
  port=$((port + 20))
}
field() {  # field OUT NAME KEY: a top-level value of the run's scenario in summary.json
  sed -n "s/.*\"$3\": *\([^,}]*\).*/\1/p" "$1/summary.json" | head -1 | tr -d '"'
}
box_clearance() {  # OUT NAME: world_sim's least robot clearance to the unmapped obstacles [m]
  sed -n 's/.*min robot clearance to the unmapped obstacles \([-0-9.]*\) m.*/\1/p' \
    "$1/$2/world_sim.log" | tail -1
}
ended() { grep -o "ended at .*" "$1/$2/world_sim.log" | tail -1; }

fail=0
check() {  # check LABEL CONDITION...
  local label=$1; shift
  if "$@"; then echo "ok   $label"; else echo "FAIL $label"; fail=1; fi
}
positive() { awk -v x="$1" 'BEGIN { exit !(x != "" && x > 0) }'; }

run unmapped_box_corridor "$tmp/box" 0
c1="$(box_clearance "$tmp/box" unmapped_box_corridor)"
echo "box alone: $(ended "$tmp/box" unmapped_box_corridor); clearance to the box $c1 m"
check "box alone: no collision" [ "$(field "$tmp/box" x collision)" = false ]
check "box alone: clearance to the box > 0 ($c1 m)" positive "$c1"
check "box alone: the robot went round it to its goal (GOAL_REACHED)" \
  grep -q "GOAL_REACHED" <<<"$(field "$tmp/box" x final_state)"

run unmapped_box_blocked "$tmp/blocked" 3
c0="$(box_clearance "$tmp/blocked" unmapped_box_blocked)"
echo "no room beside it: $(ended "$tmp/blocked" unmapped_box_blocked); clearance to the box $c0 m"
check "no room beside it: no collision" [ "$(field "$tmp/blocked" x collision)" = false ]
check "no room beside it: the robot kept away from the gap (clearance $c0 m > 1 m)" \
  awk -v x="$c0" 'BEGIN { exit !(x != "" && x > 1.0) }'

run unmapped_box_encounter "$tmp/enc" 0
c2="$(box_clearance "$tmp/enc" unmapped_box_encounter)"
echo "box and human: $(ended "$tmp/enc" unmapped_box_encounter); clearance to the box $c2 m," \
  "to the human $(field "$tmp/enc" x min_clearance_m) m"
cat "$tmp/enc/unmapped_box_encounter/transcript.txt"
check "box and human: no collision" [ "$(field "$tmp/enc" x collision)" = false ]
check "box and human: no contact with the human" \
  bash -c "! grep -q '\"contact\": *{' '$tmp/enc/summary.json'"
check "box and human: clearance to the box > 0 ($c2 m)" positive "$c2"
check "box and human: the robot went round it to its goal (GOAL_REACHED)" \
  grep -q "GOAL_REACHED" <<<"$(field "$tmp/enc" x final_state)"

run unmapped_box_corridor "$tmp/blind" 3 "--set laser=off"
c3="$(box_clearance "$tmp/blind" unmapped_box_corridor)"
echo "control, laser off: $(ended "$tmp/blind" unmapped_box_corridor); clearance to the box $c3 m"
check "control: without the scan the robot drives into the box" \
  grep -q "COLLISION\|collision" <<<"$(ended "$tmp/blind" unmapped_box_corridor) $(field "$tmp/blind" x final_state)"

[ "$fail" = 0 ] || exit 1
echo "unmapped box: seen by the laser, gone round where there is room, never squeezed past where there is none, alone and with a person"
