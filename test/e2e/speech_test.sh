#!/usr/bin/env bash
# Speech a person can hear: the paper's narrow_minimal scenario run by
# `scripts/run.sh --speech`, with espeak-ng writing each utterance as a WAV in the run directory.
# Checks, against sox's own reading of the files: one WAV per utterance said, each as long as the
# duration the dialogue manager planned with (it measured its templates with espeak-ng at start);
# every cue's words end before the crossing; no utterance starts before the previous one ended.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
for p in espeak-ng soxi; do
  command -v "$p" >/dev/null ||
    { echo "FAIL: $p is not installed (scripts/lib.sh installs espeak-ng and sox)"; exit 1; }
done
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT
name=narrow_minimal
COOPNAV_RUN_PORT_BASE=$COOPNAV_TEST_PORT_BASE bash "$src/scripts/run.sh" --no-build --speech --out "$tmp/run" \
  "$src/config/scenarios/$name.yaml" >"$tmp/run.out" 2>&1 ||
  { cat "$tmp/run.out"; echo "FAIL: run.sh --speech"; exit 1; }
dir="$tmp/run/$name"
grep -E "SAY|NOT SAID" "$dir/transcript.txt" || true
grep -q "speech: measured" "$dir/dialogue_manager.log" ||
  { echo "FAIL: the dialogue manager did not measure its texts with espeak-ng"; exit 1; }
# Every WAV's duration as sox reads it: "<file> <seconds>".
: >"$tmp/wavs.txt"
for f in "$dir"/speech/*.wav; do
  [ -e "$f" ] || break
  printf '%s %s\n' "$(basename "$f")" "$(soxi -D "$f")" >>"$tmp/wavs.txt"
done
cat "$tmp/wavs.txt"
python3 - "$tmp/run/summary.json" "$tmp/wavs.txt" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))["scenarios"][0]
wavs = {}
for line in open(sys.argv[2]):
    f, d = line.split()
    wavs[f] = float(d)
bad = []
said = []
for h in s["humans"]:
    for e in h["transcript"]:
        if e["kind"] == "say" and e["delivery"] == "said":
            said.append((h["id"], e))
if len(said) < 2:
    bad.append(f"expected round 1 and round 2 to be said, got {len(said)} utterances")
if len(wavs) != len(said):
    bad.append(f"{len(wavs)} WAV files for {len(said)} utterances said")
spans = []
for hid, e in said:
    act = e["act"].lower()
    match = [f for f in wavs if f.endswith(f"_h{hid}_r{e['round']}_{act}.wav")]
    if len(match) != 1:
        bad.append(f"round {e['round']} {act}: WAV files {match}")
        continue
    d = wavs[match[0]]
    print(f"round {e['round']} {act}: planned {e['speech_duration_s']:.3f} s, WAV {d:.3f} s, "
          f"starts {e['speech_start_s']:.2f} s after the decision, lead {e['lead_s']}")
    if abs(d - e["speech_duration_s"]) > 0.02:
        bad.append(f"{match[0]}: {d} s long, planned with {e['speech_duration_s']} s")
    if e["round"] in (1, 2) and not (e["lead_s"] is not None and e["lead_s"] > 0.0):
        bad.append(f"round {e['round']}: its words end {e['lead_s']} s before the crossing")
    start = e["t_s"] + e["speech_start_s"]
    spans.append((start, start + e["speech_duration_s"], act))
spans.sort()
for (s0, e0, a0), (s1, e1, a1) in zip(spans, spans[1:]):
    if s1 < e0 - 1e-6:
        bad.append(f"{a1} starts at {s1:.2f} s while {a0} is spoken until {e0:.2f} s")
for m in bad:
    print("FAIL", m)
print("ok: WAV files and cue timing agree" if not bad else "")
sys.exit(1 if bad else 0)
PY
