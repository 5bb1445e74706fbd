#!/usr/bin/env bash
# Every daemon under a flood at the fastest rate one peer can publish (issue 47; docs/bad-inputs.md
# "Common to every daemon"): each is started with its repository config on this test's bus and
# `coopnav_hostile --probe flood_<daemon>` floods its main input for FLOOD_S seconds. Checked:
# (a) its VmRSS stayed under its cap all along (the caps of e2e_hostile_test), (b) it still runs,
# reports, and handled 5 normal messages after the flood (the lines say how many it dropped), (c) SIGTERM stops it with exit 0 within
# 1 s. One line per daemon:  flood <daemon>: <answer> rss=<MiB> stop=<ms>
# A longer flood: COOPNAV_FLOOD_S=30 bash test/e2e/flood_test.sh (with the env of test/CMakeLists).
set -euo pipefail
build="${COOPNAV_BUILD_DIR:?}"
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
url="${LCM_DEFAULT_URL:?}"
tool="$build/tools/coopnav_hostile"
[ -x "$tool" ] || { echo "FAIL: $tool not built"; exit 1; }
FLOOD_S="${COOPNAV_FLOOD_S:-2}"
VM_LIMIT_MIB=2048
STOP_MS_MAX=1000
source "$src/test/e2e/rss_caps.sh"  # RSS_CAP_MIB, DAEMONS (config/system.yaml), DAEMON_BIN

tmp="$(mktemp -d)"
pid=""
cleanup() {
  [ -z "$pid" ] || kill -KILL "$pid" 2>/dev/null || true
  rm -rf "$tmp"
}
coopnav_trap cleanup EXIT
now_ms() { echo $(($(date +%s%N) / 1000000)); }
field() { sed -n "s/^$1: //p" <<<"$2" | tail -1; }
fail=0
t_start=$(now_ms)

for d in "${DAEMONS[@]}"; do
  why=""
  log="$tmp/$d.log"
  (
    ulimit -v $((VM_LIMIT_MIB * 1024))
    exec "${DAEMON_BIN[$d]}" --lcm-url "$url" -c "$src/config/$d.yaml"
  ) >"$log" 2>&1 &
  pid=$!
  trc=0
  out="$("$tool" --lcm-url "$url" --probe "flood_$d" --flood-s "$FLOOD_S" --timeout-s 30 \
    --pid "$pid" --rss-cap-mib "${RSS_CAP_MIB[$d]}")" || trc=$?
  [ "$trc" -eq 0 ] || why+=" not the documented answer (tool exit $trc);"
  # What the runtime dropped, per channel, once a second (none if the daemon kept up).
  drop_lines=$(grep -a -c "dropped the oldest [0-9]* waiting messages of" "$log" || true)
  t0=$(now_ms)
  kill -TERM "$pid" 2>/dev/null || true
  rc=0
  wait "$pid" || rc=$?
  ms=$(($(now_ms) - t0))
  pid=""
  [ "$rc" -eq 0 ] && [ "$ms" -le "$STOP_MS_MAX" ] || why+=" SIGTERM -> exit $rc after $ms ms;"
  line="$(field answer "$out") rss=$(field rss_mib "$out") (cap ${RSS_CAP_MIB[$d]}) stop=$ms drop_lines=$drop_lines"
  if [ -z "$why" ]; then
    echo "flood $d: $line"
  else
    echo "flood $d: FAIL:$why $line"
    while IFS= read -r l; do echo "    $l"; done <<<"$out"
    tail -5 "$log" | cut -c1-200 | sed "s/^/    $d: /"
    fail=1
  fi
done
echo "flood: $(( ($(now_ms) - t_start) / 1000 )) s"
[ "$fail" -eq 0 ] || { echo "FAIL"; exit 1; }
echo "flood: every daemon stayed under its cap and answered after the flood"
