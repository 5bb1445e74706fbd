#!/usr/bin/env bash
# The hostile publisher, short CI form (docs/bad-inputs.md "Hostile publisher"): each
# attack against the daemon(s) it targets, started with the repository's configs on this test's
# port. Bus probes (tools/hostile, `coopnav_hostile --list`) check the documented answer on the
# bus, then (a) the daemon still runs and sends a status, (b) its VmRSS stayed under the cap of
# RSS_CAP_MIB below all along, (c) SIGTERM stops it with exit 0 within 1 s (measured here).
# Start-up probes (files that are /dev/zero, duplicate keys, absurd sizes) check (d) the exit code
# within 1 s and a message naming the file or key. One line per probe:
#   probe <name>: <answer> rss=<MiB> stop=<ms>
# Every daemon runs under an address-space limit (VM_LIMIT_MIB): an attack that makes one
# allocate without bound ends in bad_alloc there instead of in the shared machine's memory.
set -euo pipefail
build="${COOPNAV_BUILD_DIR:?}"
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
url="${LCM_DEFAULT_URL:?}"
tool="$build/tools/coopnav_hostile"
[ -x "$tool" ] || { echo "FAIL: $tool not built"; exit 1; }

source "$src/test/e2e/rss_caps.sh"  # RSS_CAP_MIB, DAEMONS (config/system.yaml), DAEMON_BIN
VM_LIMIT_MIB=2048
STOP_MS_MAX=1000            # SIGTERM (or a stop signal) to exit
STARTUP_EXIT_MS_MAX=1000    # start to exit of a start-up probe
LOG_FLOOD_GROWTH_MAX_KIB=512  # band_source's log during 3000 actions with 60 kB reasons

tmp="$(mktemp -d)"
running=()  # pids of daemons started here and not yet stopped
cleanup() {
  local p
  for p in "${running[@]}"; do kill -KILL "$p" 2>/dev/null || true; done
  rm -rf "$tmp"
}
coopnav_trap cleanup EXIT
fail=0
failed=()

now_ms() { echo $(($(date +%s%N) / 1000000)); }
cfg() { echo "$src/config/$1.yaml"; }

# start NAME LOG ARGS...: a daemon in the background under the address-space limit; sets $pid.
start() {
  local name="$1" log="$2"
  shift 2
  (
    ulimit -v $((VM_LIMIT_MIB * 1024))
    exec "${DAEMON_BIN[$name]}" --lcm-url "$url" "$@"
  ) >"$log" 2>&1 &
  pid=$!
  running+=("$pid")
}

forget() {  # forget PID: no longer ours to clean up
  local p keep=()
  for p in "${running[@]}"; do [ "$p" = "$1" ] || keep+=("$p"); done
  running=(${keep[@]+"${keep[@]}"})
}

# wait_exit PID LIMIT_MS: waits for the process (killed after LIMIT_MS + 2 s); sets $rc and $ms
# (from the call). The caller sends the signal just before, so $ms is the stop time.
wait_exit() {
  local p="$1" t0 watchdog
  t0=$(now_ms)
  (sleep $((($2 + 2000) / 1000)) && kill -KILL "$p" 2>/dev/null) &
  watchdog=$!
  rc=0
  wait "$p" || rc=$?
  ms=$(($(now_ms) - t0))
  kill "$watchdog" 2>/dev/null || true
  wait "$watchdog" 2>/dev/null || true
  forget "$p"
}

# stop PID: SIGTERM, then checks exit 0 within STOP_MS_MAX; appends to $why; sets $stop_ms.
stop() {
  kill -TERM "$1" 2>/dev/null || true
  wait_exit "$1" "$STOP_MS_MAX"
  stop_ms="$ms"
  if [ "$rc" -ne 0 ] || [ "$ms" -gt "$STOP_MS_MAX" ]; then
    why+=" SIGTERM -> exit $rc after $ms ms;"
  fi
}

report() {  # report PROBE ANSWER RSS STOP
  if [ -z "$why" ]; then
    echo "probe $1: $2 rss=$3 stop=$4"
  else
    echo "probe $1: FAIL:$why ($2) rss=$3 stop=$4"
    fail=1
    failed+=("$1")
  fi
}

field() { sed -n "s/^$1: //p" <<<"$2" | tail -1; }

# bus_probe PROBE DAEMONS [ARGS...]: starts DAEMONS ("a+b"), each with its repository config and
# ARGS, runs the probe against them, checks that each stops in time. Leaves the probe's output in
# $out and the daemons' logs in $tmp/PROBE.DAEMON.log; $why holds what failed.
bus_probe() {
  local probe="$1" daemons="$2" d
  shift 2
  local pids=() tool_args=()
  why=""
  for d in ${daemons//+/ }; do
    start "$d" "$tmp/$probe.$d.log" -c "$(cfg "$d")" "$@"
    pids+=("$pid")
    tool_args+=(--pid "$pid" --rss-cap-mib "${RSS_CAP_MIB[$d]}")
  done
  local trc=0
  out="$("$tool" --lcm-url "$url" --probe "$probe" --timeout-s 30 "${tool_args[@]}")" || trc=$?
  [ "$trc" -eq 0 ] || why+=" not the documented answer (tool exit $trc);"
  hook_after_probe "$probe"
  local stops=()
  for p in "${pids[@]}"; do
    stop "$p"
    stops+=("$stop_ms")
  done
  report "$probe" "$(field answer "$out")" "$(field rss_mib "$out")" "$(IFS=/; echo "${stops[*]}")"
  if [ -n "$why" ]; then
    while IFS= read -r line; do echo "    $line"; done <<<"$out"
    for d in ${daemons//+/ }; do tail -5 "$tmp/$probe.$d.log" | cut -c1-200 | sed "s/^/    $d: /"; done
  fi
}

# Checks of what only this script sees (logs, the journal file), between the probe and the stop.
hook_after_probe() {
  local log
  case "$1" in
    action_reason_forgery)
      log="$tmp/$1.band_source.log"
      # A line of the log that the reason started, or a raw escape byte a terminal would obey.
      if grep -a -E '^\[0000-00-00|^FORGED' "$log" >/dev/null; then why+=" forged line in the log;"; fi
      if grep -a -P '\x1b|\r' "$log" >/dev/null; then why+=" raw control characters in the log;"; fi
      if ! grep -a -F '\x0A[0000-00-00' "$log" >/dev/null; then
        why+=" the reason is not logged with its newline as \\x0A;"
      fi
      ;;
    action_reason_flood)
      log="$tmp/$1.band_source.log"
      local kib=$(($(stat -c %s "$log") / 1024))
      out+=$'\n'"answer: $(field answer "$out"); log ${kib} KiB (cap ${LOG_FLOOD_GROWTH_MAX_KIB} KiB)"
      [ "$kib" -le "$LOG_FLOOD_GROWTH_MAX_KIB" ] || why+=" log grew to $kib KiB;"
      grep -a -q 'suppressed [0-9]* lines' "$log" || why+=" no \"suppressed N lines\" line;"
      ;;
    journal_flood)
      local j="$tmp/state/path_assessor.journal" size1 size2
      size1=$(stat -c %s "$j" 2>/dev/null || echo 0)
      # More of the same: a journal at its cap stays as it is.
      "$tool" --lcm-url "$url" --probe journal_flood --timeout-s 10 >/dev/null || true
      size2=$(stat -c %s "$j" 2>/dev/null || echo 0)
      out+=$'\n'"answer: $(field answer "$out"); journal $size1 then $size2 bytes"
      # The cap, plus the record that says the journal is full.
      [ "$size1" -le $((1024 * 1024 + 4096)) ] || why+=" journal of $size1 bytes over 1 MiB;"
      [ "$size2" -eq "$size1" ] || why+=" journal grew from $size1 to $size2 bytes at its cap;"
      ;;
  esac
}

# startup_probe PROBE DAEMON RC PATTERN ARGS...: the daemon must exit RC within
# STARTUP_EXIT_MS_MAX and say PATTERN (an extended regex: the file or the key) in its output.
startup_probe() {
  local probe="$1" daemon="$2" want_rc="$3" pattern="$4"
  shift 4
  local log="$tmp/$probe.$daemon.log"
  why=""
  start "$daemon" "$log" --log-level info "$@"
  wait_exit "$pid" "$STARTUP_EXIT_MS_MAX"
  [ "$rc" -eq "$want_rc" ] || why+=" exit $rc, not $want_rc;"
  [ "$ms" -le "$STARTUP_EXIT_MS_MAX" ] || why+=" took $ms ms;"
  [ -e "$log" ] || { why+=" its log $log is gone;"; : >"$log"; }
  grep -a -E -q -- "$pattern" "$log" || why+=" the message does not name /$pattern/;"
  local msg
  msg="$(grep -a -E -m1 -- "$pattern" "$log" | sed 's/^\[[^]]*\] \[[^]]*\] \[[^]]*\] //' |
    cut -c1-90 || true)"
  report "$probe" "exit $rc: ${msg:-$(tail -1 "$log" | cut -c1-90)}" - "$ms"
  [ -z "$why" ] || tail -3 "$log" | cut -c1-200 | sed 's/^/    /' || true
}

# --- the hostile files ---
ln -s /dev/zero "$tmp/zero_map.yaml"
ln -s /dev/zero "$tmp/zero_map.bt"
ln -s /dev/zero "$tmp/zero_scenario.yaml"
ln -s /dev/zero "$tmp/zero_config.yaml"
map_meta="origin: [-5.0, -10.0, 0.0]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196"
printf 'image: /dev/zero\nresolution: 0.05\n%s\n' "$map_meta" >"$tmp/ros_image_zero.yaml"
printf 'image: %s\nresolution: 1e-9\n%s\n' "$src/config/maps/open.pgm" "$map_meta" \
  >"$tmp/ros_tiny_resolution.yaml"
# A map that takes seconds to load (2000 x 2000 cells, under max_map_cells): the stop signal
# comes while it loads.
cat >"$tmp/slow_map.yaml" <<'EOF'
resolution_m: 0.01
walls:
  - {x0_m: 0.0, y0_m: 0.0, x1_m: 20.0, y1_m: 0.0, thickness_m: 0.1}
  - {x0_m: 0.0, y0_m: 20.0, x1_m: 20.0, y1_m: 20.0, thickness_m: 0.1}
  - {x0_m: 0.0, y0_m: 0.0, x1_m: 0.0, y1_m: 20.0, thickness_m: 0.1}
  - {x0_m: 20.0, y0_m: 0.0, x1_m: 20.0, y1_m: 20.0, thickness_m: 0.1}
EOF
{ cat "$(cfg path_assessor)"; echo "gamma: 0.5"; } >"$tmp/duplicate_key.yaml"
# open_minimal with 65 humans (the wire carries 64): in rows across the 6 m corridor.
{
  sed '/^humans:/,$d' "$src/config/scenarios/open_minimal.yaml" | sed 's/enabled: true/enabled: false/'
  echo "humans:"
  for i in $(seq 1 65); do
    x=$(awk -v i="$i" 'BEGIN { printf "%.1f", 8 + ((i - 1) % 13) * 1.5 }')
    y=$(awk -v i="$i" 'BEGIN { printf "%.1f", 1.0 + int((i - 1) / 13) * 1.0 }')
    echo "  - {id: $i, start: {x_m: $x, y_m: $y, theta_rad: 3.14159}, goal: {x_m: 2.5, y_m: $y}, behaviour: minimal, speed_m_s: 1.0}"
  done
} >"$tmp/crowd_scenario.yaml"

t_start=$(now_ms)

# --- start-up: files that are /dev/zero (7), bad configs, scenarios and maps (9) ---
startup_probe map_is_dev_zero band_source 3 '/dev/zero' -c "$(cfg band_source)" \
  --set map_file=/dev/zero
startup_probe map_symlink_to_dev_zero obstacle_distance_server 3 'zero_map\.yaml|/dev/zero' \
  -c "$(cfg obstacle_distance_server)" --set "map_file=$tmp/zero_map.yaml"
startup_probe ros_map_image_dev_zero obstacle_distance_server 3 '/dev/zero' \
  -c "$(cfg obstacle_distance_server)" --set "map_file=$tmp/ros_image_zero.yaml"
startup_probe bt_symlink_to_dev_zero band_source 3 'zero_map\.bt|/dev/zero' \
  -c "$(cfg band_source)" --set "map_file=$tmp/zero_map.bt"
startup_probe scenario_symlink_to_dev_zero world_sim 3 'zero_scenario\.yaml|/dev/zero' \
  -c "$(cfg world_sim)" --set "scenario=$tmp/zero_scenario.yaml"
startup_probe config_is_dev_zero situation_assessor 2 '/dev/zero' -c /dev/zero
startup_probe config_symlink_to_dev_zero dialogue_manager 2 'zero_config\.yaml|/dev/zero' \
  -c "$tmp/zero_config.yaml"
startup_probe config_duplicate_key path_assessor 2 'gamma' -c "$tmp/duplicate_key.yaml"
startup_probe scenario_65_humans world_sim 3 'crowd_scenario\.yaml|65|64' -c "$(cfg world_sim)" \
  --set "scenario=$tmp/crowd_scenario.yaml"
startup_probe ros_map_resolution_1e-9 obstacle_distance_server 3 'ros_tiny_resolution\.yaml' \
  -c "$(cfg obstacle_distance_server)" --set "map_file=$tmp/ros_tiny_resolution.yaml"

# SIGTERM while a slow map loads (7): exit 0 within 1 s. A daemon sends its first status (RUNNING)
# once it is ready: `coopnav_ctl wait-ready`, listening from before the start, hears one only if
# the map had loaded before the signal.
why=""
"$build/tools/coopnav_ctl" --lcm-url "$url" wait-ready obstacle_distance_server --announce \
  --timeout-s 30 >"$tmp/startup_sigterm.ready" 2>&1 &
ready_pid=$!
running+=("$ready_pid")
for _ in $(seq 1 100); do grep -q '^listening' "$tmp/startup_sigterm.ready" && break; sleep 0.05; done
start obstacle_distance_server "$tmp/startup_sigterm.log" -c "$(cfg obstacle_distance_server)" \
  --set "map_file=$tmp/slow_map.yaml"
sleep 0.3
kill -0 "$pid" 2>/dev/null || why+=" exited before the signal (the map loaded too fast);"
stop "$pid"
# A status sent before the exit has reached the listener by now.
sleep 0.2
kill -TERM "$ready_pid" 2>/dev/null || true
ready_rc=0
wait "$ready_pid" || ready_rc=$?
forget "$ready_pid"
if [ "$ready_rc" -eq 0 ]; then
  why+=" the map had loaded before the signal (a RUNNING status was heard): not a stop during start-up;"
fi
report sigterm_during_startup "SIGTERM while loading a 2000x2000 map: exit $rc" - "$stop_ms"

# --- bus probes ---
bus_probe bands_time_span situation_assessor
bus_probe agent_states_int64_max band_source
bus_probe reference_paths_int64_max path_assessor
bus_probe situation_int64_max dialogue_manager
bus_probe backlog_band_source band_source
bus_probe backlog_situation_assessor situation_assessor
bus_probe reference_path_id_flood path_assessor+situation_assessor
bus_probe situation_id_flood dialogue_manager
bus_probe future_step_flood path_assessor+situation_assessor
bus_probe dist_reply_status_channel obstacle_distance_server
bus_probe dist_reply_channel_flood obstacle_distance_server
bus_probe action_reason_forgery band_source
bus_probe action_reason_flood band_source
mkdir -p "$tmp/state"
bus_probe journal_flood path_assessor --state-dir "$tmp/state" --set limits.journal_max_mib=1

# --- 10. stop signals: a clean stop with a final status ---
for sig in HUP USR1; do
  why=""
  start path_assessor "$tmp/signal_$sig.log" -c "$(cfg path_assessor)"
  daemon=$pid
  "$tool" --lcm-url "$url" --watch --pid "$daemon" --await-stopping --timeout-s 20 \
    >"$tmp/signal_$sig.out" &
  watcher=$!
  for _ in $(seq 1 200); do grep -q '^ready' "$tmp/signal_$sig.out" && break; sleep 0.05; done
  kill -"$sig" "$daemon"
  wait_exit "$daemon" "$STOP_MS_MAX"
  wrc=0
  wait "$watcher" || wrc=$?
  [ "$rc" -eq 0 ] && [ "$ms" -le "$STOP_MS_MAX" ] || why+=" SIG$sig -> exit $rc after $ms ms;"
  [ "$wrc" -eq 0 ] || why+=" $(field answer "$(cat "$tmp/signal_$sig.out")");"
  report "sig${sig,,}_stops_cleanly" "SIG$sig: exit $rc, $(field answer "$(cat "$tmp/signal_$sig.out")")" - "$ms"
done

# --- 10. two daemons of one name on one bus: each DEGRADED naming the other, both go on ---
why=""
start path_assessor "$tmp/twin_a.log" -c "$(cfg path_assessor)"
pid_a=$pid
start path_assessor "$tmp/twin_b.log" -c "$(cfg path_assessor)"
pid_b=$pid
twin_answer=""
for pair in "$pid_a $pid_b a" "$pid_b $pid_a b"; do
  read -r me other tag <<<"$pair"
  # The first status of the other may come a second after start: allow two status periods.
  o=""
  for _ in 1 2 3; do
    if o="$("$tool" --lcm-url "$url" --watch --pid "$me" --expect-state DEGRADED \
      --expect-detail "pid $other" --rss-cap-mib "${RSS_CAP_MIB[path_assessor]}" --timeout-s 5)"; then
      break
    fi
  done
  [ "$(field verdict "$o")" = ok ] || why+=" $tag: $(field answer "$o");"
  grep -a -E "\[warn(ing)?\].*$other" "$tmp/twin_$tag.log" >/dev/null || why+=" $tag: no warn line naming pid $other;"
  twin_answer+="$tag DEGRADED naming pid $other; "
done
stops=()
for p in "$pid_a" "$pid_b"; do
  kill -0 "$p" 2>/dev/null || why+=" pid $p stopped on its own;"
  stop "$p"
  stops+=("$stop_ms")
done
report duplicate_name_on_one_bus "${twin_answer}both kept running" - "$(IFS=/; echo "${stops[*]}")"

echo "hostile: $(( ($(now_ms) - t_start) / 1000 )) s"
if [ "$fail" -ne 0 ]; then
  echo "FAIL: ${#failed[@]} probes: ${failed[*]}"
  exit 1
fi
echo "hostile: every probe got its documented answer"
