# One scenario run with every daemon as its own process: the launch that scripts/run.sh (the
# paper's experiment) and scripts/faults.sh (kills, an absent distance server, message loss)
# share. Sourced after lib.sh, not executed.
#
#   coopnav_run_scenario SCENARIO.yaml DIR PORT
#     Starts the recorder (DIR/<name>.lcm, tools/record), the distance server, the band source, the assessors
#     and the dialogue manager, waits until they are ready, runs world_sim in lockstep and stops
#     everything. Returns world_sim's exit code (DIR/world_sim.log). Every process logs to
#     DIR/<process>.log (appended to when a daemon is started again).
#
# Knobs (variables set by the caller; all optional):
#   COOPNAV_ABSENT="d1 d2"      daemons not started at all (e.g. obstacle_distance_server)
#   COOPNAV_STATE=1             every daemon gets --state-dir DIR/state (restart journal)
#   COOPNAV_LOSS=0.1            each daemon on a port of its own, joined by coopnav_lossy_relay
#                               dropping that fraction of every forwarded message (seed
#                               COOPNAV_LOSS_SEED); the logger and the scripts hear everything
#   COOPNAV_PROFILE=calibrated  the assessment profile (default paper): the path assessor runs
#                               config/path_assessor_<profile>.yaml (paper: path_assessor.yaml)
#                               and the dialogue manager acts on that profile's assessments
#   COOPNAV_DAEMON_ARGS_<name>  extra arguments of that daemon or of world_sim (word-split),
#                               e.g. --set k=v
#   coopnav_scenario_hook       a function run while world_sim runs (in the foreground of the
#                               script, world_sim in the background): faults.sh kills there
#   coopnav_scenario_after_hook a function run after world_sim ended, before the daemons are
#                               stopped (faults.sh checks that none of them died)
# After the launch, COOPNAV_DAEMON_PID[<name>] holds each daemon's pid and coopnav_start_daemon
# NAME starts one again with the same command line.

COOPNAV_DAEMONS=(obstacle_distance_server band_source situation_assessor path_assessor
  dialogue_manager)
declare -A COOPNAV_DAEMON_PID=()
declare -A COOPNAV_DAEMON_URL=()

# LCM URL of a process of the current run: the shared one, or with loss its own port.
coopnav_daemon_url() {
  local url="${COOPNAV_DAEMON_URL[$1]:-}"
  echo "${url:-$LCM_DEFAULT_URL}"
}

coopnav_start_daemon() {  # NAME
  local d="$1" args=()
  case "$d" in
    obstacle_distance_server | band_source)
      args=(-c "$_cn_cfg/$d.yaml" --set "map_file=$_cn_scenario") ;;
    path_assessor)
      if [ "${COOPNAV_PROFILE:-paper}" = paper ]; then
        args=(-c "$_cn_cfg/$d.yaml")
      else
        args=(-c "$_cn_cfg/${d}_${COOPNAV_PROFILE}.yaml")
      fi ;;
    dialogue_manager)
      args=(-c "$_cn_cfg/$d.yaml" --set "assessment_profile=${COOPNAV_PROFILE:-paper}") ;;
    *) args=(-c "$_cn_cfg/$d.yaml") ;;
  esac
  # The distance server keeps no state across requests: nothing to journal.
  if [ "${COOPNAV_STATE:-0}" = 1 ] && [ "$d" != obstacle_distance_server ]; then
    args+=(--state-dir "$_cn_dir/state")
  fi
  local extra_var="COOPNAV_DAEMON_ARGS_$d"
  local extra=()
  read -r -a extra <<<"${!extra_var:-}"
  "$(coopnav_bin "$d")" "${args[@]}" "${extra[@]}" --lcm-url "$(coopnav_daemon_url "$d")" \
    >>"$_cn_dir/$d.log" 2>&1 &
  COOPNAV_DAEMON_PID[$d]=$!
  COOPNAV_PIDS+=($!)
}

coopnav_run_scenario() {  # SCENARIO DIR PORT
  _cn_scenario="$1"
  _cn_dir="$2"
  _cn_cfg="$COOPNAV_ROOT/config"
  local port="$3" name ctl rc=0 d
  name="$(basename "$_cn_scenario" .yaml)"
  ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"
  mkdir -p "$_cn_dir"
  echo "$_cn_scenario" >"$_cn_dir/scenario.path"  # replay.sh finds the map through it
  export LCM_DEFAULT_URL="udpm://239.255.76.67:$port?ttl=0&recv_buf_size=4194304"
  COOPNAV_DAEMON_PID=()
  COOPNAV_DAEMON_URL=()
  if [ -n "${COOPNAV_LOSS:-}" ]; then
    # Every process on a port of its own; the relay joins them (lossless towards the logger and
    # the scripts, which stay on the shared URL).
    local p=$((port + 1)) eps=()
    for d in "${COOPNAV_DAEMONS[@]}" world_sim; do
      COOPNAV_DAEMON_URL[$d]="udpm://239.255.76.67:$p?ttl=0&recv_buf_size=4194304"
      eps+=(--endpoint "${COOPNAV_DAEMON_URL[$d]}")
      p=$((p + 1))
    done
    coopnav_spawn "$_cn_dir/relay.log" "$COOPNAV_BUILD_DIR/tools/coopnav_lossy_relay" \
      "${eps[@]}" --lossless "$LCM_DEFAULT_URL" --loss "$COOPNAV_LOSS" \
      --seed "${COOPNAV_LOSS_SEED:-1}"
  fi
  coopnav_record "$_cn_dir/$name.lcm" 'COOPNAV_.*' "$_cn_dir/record.log"
  local ready=()
  for d in "${COOPNAV_DAEMONS[@]}"; do
    case " ${COOPNAV_ABSENT:-} " in *" $d "*) continue ;; esac
    coopnav_start_daemon "$d"
    ready+=("$d")
  done
  if ! "$ctl" wait-ready "${ready[@]}" --timeout-s 60; then
    echo "coopnav: daemons did not come up for $name; see $_cn_dir/*.log" >&2
    coopnav_stop_all
    return 1
  fi
  sleep 0.3  # the recorder subscribes before the first step
  local sim_extra=()
  read -r -a sim_extra <<<"${COOPNAV_DAEMON_ARGS_world_sim:-}"
  "$(coopnav_bin world_sim)" -c "$_cn_cfg/world_sim.yaml" --set "scenario=$_cn_scenario" \
    "${sim_extra[@]}" --lcm-url "$(coopnav_daemon_url world_sim)" >"$_cn_dir/world_sim.log" 2>&1 &
  local sim=$!
  if declare -F coopnav_scenario_hook >/dev/null; then coopnav_scenario_hook "$name" || true; fi
  wait "$sim" || rc=$?
  coopnav_wait_recorded "$_cn_dir/$name.lcm"
  if declare -F coopnav_scenario_after_hook >/dev/null; then coopnav_scenario_after_hook "$name"; fi
  coopnav_stop_all
  return "$rc"
}
