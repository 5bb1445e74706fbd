#!/usr/bin/env bash
# lcm-spy as a user runs it (scripts/spy.sh, README "Monitoring"), in a real X display (Xvfb),
# against a replayed log: it must find the project's types and list the log's channels with
# them. A Java agent inside lcm-spy's JVM (test/e2e/spy_probe/SpyProbe.java) reads the channel
# table lcm-spy shows and screenshots the display; the screenshot is kept beside the test's output
# (COOPNAV_ARTIFACT_DIR, default build/test_artifacts/spy).
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
out="${COOPNAV_ARTIFACT_DIR:-$COOPNAV_BUILD_DIR/test_artifacts/spy}"
tmp="$(mktemp -d)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$tmp"
}
coopnav_trap cleanup EXIT
mkdir -p "$out"
rm -f "$out"/spy.png "$out"/spy_channels.tsv

for tool in Xvfb java javac jar lcm-logplayer; do
  command -v "$tool" >/dev/null ||
    { echo "FAIL: $tool is missing (scripts/lib.sh installs xvfb, default-jdk-headless, liblcm-bin)"; exit 1; }
done

# The probe, built here from its one source file (it is test code, not part of the build).
mkdir -p "$tmp/probe"
javac -d "$tmp/probe" "$src/test/e2e/spy_probe/SpyProbe.java"
printf 'Premain-Class: SpyProbe\n' >"$tmp/manifest"
jar cfm "$tmp/spy_probe.jar" "$tmp/manifest" -C "$tmp/probe" .

# A display of our own: the first free number from 90.
disp=90
while [ -e "/tmp/.X11-unix/X$disp" ] || [ -e "/tmp/.X$disp-lock" ]; do disp=$((disp + 1)); done
Xvfb ":$disp" -screen 0 1280x800x24 -nolisten tcp >"$tmp/xvfb.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -e "/tmp/.X11-unix/X$disp" ] && break; sleep 0.1; done
[ -e "/tmp/.X11-unix/X$disp" ] || { cat "$tmp/xvfb.log"; echo "FAIL: Xvfb :$disp did not start"; exit 1; }

url="udpm://239.255.76.67:${COOPNAV_TEST_PORT_BASE:?}?ttl=0"
DISPLAY=":$disp" LCM_DEFAULT_URL="$url" JAVA_TOOL_OPTIONS="-javaagent:$tmp/spy_probe.jar=$out" \
  bash "$src/scripts/spy.sh" >"$out/spy.log" 2>&1 &
pids+=($!)
# lcm-spy needs a few seconds to start its JVM and scan the classpath for types.
for _ in $(seq 300); do grep -q 'LCM types' "$out/spy.log" 2>/dev/null && break; sleep 0.1; done

gunzip -c "$src/test/data/golden/narrow_minimal.lcm.gz" >"$tmp/run.lcm"
lcm-logplayer -l "$url" -s 1 "$tmp/run.lcm" >"$tmp/player.log" 2>&1 &
pids+=($!)

# The channels the log carries, each with its type: what lcm-spy must list.
expected=(COOPNAV_AGENT_STATES:agent_states_t COOPNAV_BANDS:bands_t
  COOPNAV_REFERENCE_PATHS:reference_paths_t COOPNAV_SIM_STATUS:sim_status_t)
listed() { grep -qx "${1%%:*}	${1#*:}" "$out/spy_channels.tsv" 2>/dev/null; }
all_listed() {
  for e in "${expected[@]}"; do listed "$e" || return 1; done
  [ -f "$out/spy.png" ]
}
for _ in $(seq 60); do all_listed && break; sleep 1; done

fail=0
if grep -Eq 'Found [1-9][0-9]* LCM types' "$out/spy.log"; then
  echo "ok   lcm-spy: $(grep -Eo 'Found [0-9]+ LCM types' "$out/spy.log" | head -1)"
else
  echo "FAIL lcm-spy did not find the project's types:"; cat "$out/spy.log"; fail=1
fi
for e in "${expected[@]}"; do
  if listed "$e"; then echo "ok   lcm-spy lists ${e%%:*} as ${e#*:}"
  else echo "FAIL lcm-spy does not list ${e%%:*} as ${e#*:}"; fail=1; fi
done
if grep -q $'\t??' "$out/spy_channels.tsv" 2>/dev/null; then
  echo "FAIL lcm-spy lists channels of unknown type:"; grep $'\t??' "$out/spy_channels.tsv"; fail=1
fi
if [ -s "$out/spy.png" ]; then echo "ok   screenshot: $out/spy.png"
else echo "FAIL no screenshot of lcm-spy"; fail=1; fi
[ "$fail" = 0 ] || { echo "--- channel table:"; cat "$out/spy_channels.tsv" 2>/dev/null || true; }
exit "$fail"
