#!/usr/bin/env bash
# Faults, shortened (README "Faults"; the full run is scripts/faults.sh): the four paper
# scenarios, each run clean, with one daemon killed (-9) at a seeded random step and started
# again with its journal, and under 10 % message loss; narrow_minimal also without the distance
# server for the whole run (it collided before the precautionary dock: it must end without a
# collision, docking as a precaution).
# Each run must complete with the clean run's decisions (or say in the transcript that they are
# degraded), never a dock the clean run did not have unless it says it is a precaution, never a
# daemon dying on its own; under loss the decisions must be the clean ones exactly.
# Selection (13 runs, ~3 min on the shared 2-core machine under load): one kill per scenario, the daemons
# with state to recover (the distance server is stateless: its absence is the absent run); the
# loss runs of all four scenarios: a lost answer to the last step is only recovered because the
# world waits for the last step's acks too (narrow_minimal with relay seed 20442 loses one).
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT
fail=0
# Ports of this test only (its block from COOPNAV_TEST_PORT_BASE, test/CMakeLists.txt).
COOPNAV_FAULT_PORT_BASE=$COOPNAV_TEST_PORT_BASE bash "$src/scripts/faults.sh" --no-build --out "$tmp/a" \
  --scenarios "open_facilitating open_minimal narrow_facilitating narrow_minimal" \
  --kill "situation_assessor dialogue_manager path_assessor band_source" \
  --kills-per-scenario 1 --absent-in narrow_minimal --seed 7 || fail=1
if [ "$fail" -ne 0 ]; then
  for f in "$tmp"/*/*/*/world_sim.log; do echo "--- $f"; tail -3 "$f"; done
  echo "FAIL: fault runs"
fi
[ "$fail" -eq 0 ] && echo "faults: all checks pass"
exit "$fail"
