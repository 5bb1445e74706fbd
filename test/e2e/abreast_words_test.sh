#!/usr/bin/env bash
# Words that match actions (issue 44), end to end as a user runs it: two people walking abreast
# towards the robot in a 2.5 m corridor (test/data/scenarios/abreast_2_5_minimal.yaml). The run
# must reach the goal without contact (scripts/run.sh exit 0), and summary.json's dialogue
# checks, read from the log alone, must be empty: no action contradicting the words (a dock after
# "I am passing on your right." without words of making room), no group told two sides or the
# same round twice, nothing said to someone not being crossed.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT
COOPNAV_RUN_PORT_BASE=$COOPNAV_TEST_PORT_BASE bash "$src/scripts/run.sh" --no-build --out "$tmp/run" \
  "$src/test/data/scenarios/abreast_2_5_minimal.yaml" >"$tmp/run.out" 2>&1 ||
  { cat "$tmp/run.out"; echo "FAIL: run.sh"; exit 1; }
grep -E "SAY|NOT SAID|ACTION" "$tmp/run/abreast_2_5_minimal/transcript.txt" || true
python3 - "$tmp/run/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))["scenarios"][0]
d = s["dialogue_checks"]
bad = [f"{k}: {d[k]}" for k in ("action_contradicts_words", "contradictions", "told_twice",
                                 "said_to_not_crossing") if d[k]]
if d["said"] == 0:
    bad.append("nothing said to the pair")
print(f"{s['final_state']}, said {d['said']}, action_words_too_late {d['action_words_too_late']}")
for m in bad:
    print("FAIL", m)
sys.exit(1 if bad else 0)
PY
echo "two abreast in 2.5 m: the words and the actions agree"
