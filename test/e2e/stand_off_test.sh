#!/usr/bin/env bash
# A mutual wait resolved with words (issue 44), end to end: a 1.9 m corridor with a
# late-facilitating person who makes room and waits for the robot docked for them
# (test/data/scenarios/corridor_1_9_late_facilitating.yaml). The run must reach the goal without
# contact (scripts/run.sh exit 0); summary.json's longest mutual wait must stay under the 10 s a
# population counts as a stalemate; the robot must have ended the stand-off in words that were
# said ("Thank you, I will go first." or "I will go now.") with a RESUME at the same step; and the
# dialogue checks, read from the log alone, must be empty.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT
name=corridor_1_9_late_facilitating
COOPNAV_RUN_PORT_BASE=$COOPNAV_TEST_PORT_BASE bash "$src/scripts/run.sh" --no-build --out "$tmp/run" \
  "$src/test/data/scenarios/$name.yaml" >"$tmp/run.out" 2>&1 ||
  { cat "$tmp/run.out"; echo "FAIL: run.sh"; exit 1; }
transcript="$tmp/run/$name/transcript.txt"
grep -E "SAY|NOT SAID|ACTION" "$transcript" || true
python3 - "$tmp/run/summary.json" "$transcript" <<'PY'
import json, re, sys
s = json.load(open(sys.argv[1]))["scenarios"][0]
lines = open(sys.argv[2]).read().splitlines()
bad = []
if s["max_mutual_wait_s"] > 10.0:
    bad.append(f"a mutual wait of {s['max_mutual_wait_s']:.1f} s (over 10 s: a stalemate)")
said = [l for l in lines if re.search(r"\bSAY INFORM_(GOING_FIRST|RESUMING)\b", l)]
if not said:
    bad.append("no stand-off ended in words that were said")
for l in said:
    t = l.split()[0]
    if not any(m.split()[0] == t and "ACTION RESUME" in m for m in lines):
        bad.append(f"words without a RESUME at the same time: {l}")
d = s["dialogue_checks"]
bad += [f"{k}: {d[k]}" for k in ("action_contradicts_words", "contradictions", "told_twice",
                                  "said_to_not_crossing") if d[k]]
print(f"{s['final_state']}, longest mutual wait {s['max_mutual_wait_s']:.1f} s, "
      f"stalled {s['stalled_s']:.1f} s, said {d['said']}")
for m in bad:
    print("FAIL", m)
sys.exit(1 if bad else 0)
PY
echo "a stand-off in a 1.9 m corridor: resolved within a bounded time, said and done"
