#!/usr/bin/env bash
# Log replay with golden output: a recorded lockstep run (the world's side only: agent states,
# goals, bands, reference paths, sim status; test/data/golden/*.lcm.gz) played with
# lcm-logplayer into fresh assessors and a fresh dialogue manager must give the golden
# transcript byte for byte. Guards the assessors' and dialogue manager's decisions against
# unintended change; regenerate with test/data/golden/README.md when a change is intended.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
tmp="$(mktemp -d)"
# lcm-logplayer publishes over UDP without flow control: on a loaded CI machine a fast replay can
# lose a datagram, and the transcript's counts would differ. The golden log's stamps are those of
# a lockstep run replayed at 4x (~300 steps per second); 0.1 plays it at ~30 steps per second.
coopnav_trap 'rm -rf "$tmp"' EXIT
fail=0
port=$COOPNAV_TEST_PORT_BASE
for gz in "$src"/test/data/golden/*.lcm.gz; do
  name="$(basename "$gz" .lcm.gz)"
  gunzip -c "$gz" >"$tmp/$name.lcm"
  COOPNAV_REPLAY_PORT=$port bash "$src/scripts/replay.sh" --no-build --speed 0.1 \
    --map "$src/config/scenarios/$name.yaml" --out-dir "$tmp/$name" "$tmp/$name.lcm" \
    >"$tmp/$name.txt" 2>"$tmp/$name.err" || { cat "$tmp/$name.err"; fail=1; }
  port=$((port + 1))
  if cmp -s "$tmp/$name.txt" "$src/test/data/golden/$name.transcript"; then
    echo "ok   $name: replayed transcript equals the golden one"
  else
    echo "FAIL $name: replayed transcript differs from test/data/golden/$name.transcript"
    diff "$src/test/data/golden/$name.transcript" "$tmp/$name.txt" | head -30
    fail=1
  fi
done
exit "$fail"
