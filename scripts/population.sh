#!/usr/bin/env bash
# A population of head-on corridor (or crowd) encounters (docs/population.md): generates N
# scenario files from a seed (tools/population), runs them JOBS at a time, each on a udpm port of
# its own and in a folder of its own, plus one run without humans per corridor layout (the
# time-to-goal baseline), and writes DIR/population.json and DIR/population.txt. Exit non-zero:
# 1 a contact with the robot at fault; 4 a failed dialogue check (words to someone not crossed, a
# contradiction, a group told twice, unaddressed among several); 5 a run ended in any contact, a
# standstill, the time limit or a mutual wait over 10 s (why on stderr); 3 a run left no summary;
# muted twins included. A line per finished run says where it stands (a terminal: one line).
#
#   scripts/population.sh [--n N] [--seed S] [-j JOBS] [--out DIR] [--no-build]
#                         [--tracker-noise] [--goals-withheld] [--profile paper|calibrated|forecast]
#                         [--realistic-timing] [--cue-effect | --crowd]
#   (defaults: N 200, seed 1, JOBS = cores (4 per core at most), DIR runs/population-<seed>;
#   --tracker-noise: the humans as a tracker sees them, σ 0.05 m, 5 % missed, one id switch;
#   --goals-withheld: the humans' goals are not published, the band source infers them, and the
#   table says how often the region planned with at round 1 is the one walked to;
#   --profile: the config profile, as scripts/run.sh;
#   --realistic-timing: people who yield of their own accord start at an onset drawn from real
#   walkers' (world_sim avoidance_timing=realistic, docs/scenario-format.md);
#   --cue-effect: every head-on human responsive (the other draws as the seed's), every encounter
#   run twice, speaking in DIR/runs/<name> and with the dialogue manager muted (--set muted=true)
#   in DIR/runs/<name>_muted, same scenario file and seed; the table adds what the spoken cue
#   changes (docs/population.md "Speaking and muted"); default DIR runs/population-<seed>-cue;
#   --crowd: crowd encounters, 2-10 people: flows both ways, a group abreast, people standing
#   talking by a wall, a junction (docs/population.md "Crowds"); default DIR
#   runs/population-<seed>-crowd)
# Environment: COOPNAV_POP_PORT_BASE (7400; run k of JOBS uses base + its slot),
# COOPNAV_POP_RUN_TIMEOUT_S (900: wall seconds before a run is stopped).
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
source "$COOPNAV_ROOT/scripts/scenario.sh"

ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"
pop="$COOPNAV_BUILD_DIR/tools/population/coopnav_population"

# One run, in a process of its own (so that a timeout can stop it and its daemons):
#   population.sh --worker SCENARIO RUN_DIR PORT
if [ "${1:-}" = "--worker" ]; then
  coopnav_trap coopnav_stop_all EXIT
  coopnav_trap 'coopnav_stop_all; exit 143' INT TERM
  scenario="$2" dir="$3" port="$4"
  name="$(basename "$scenario" .yaml)"  # a muted twin runs its encounter's file: same name
  rm -rf "$dir"
  mkdir -p "$dir"
  start_s=$(date +%s.%N)
  rc=0
  coopnav_run_scenario "$scenario" "$dir" "$port" || rc=$?
  echo "$rc" >"$dir/world_sim.exit"
  if [ -f "$dir/$name.lcm" ]; then
    "$ctl" summarize "$dir/$name.lcm" --scenario "$name" --out "$dir/summary.json" \
      >"$dir/summarize.log" 2>&1 || true
  fi
  # For the progress line of the script that started this worker: state, simulated and wall s.
  state="$(grep -o '"final_state": "[A-Z_]*"' "$dir/summary.json" 2>/dev/null | head -n 1 |
    cut -d'"' -f4 || true)"
  sim_s="$(grep -o '"sim_time_s": [0-9.eE+-]*' "$dir/summary.json" 2>/dev/null | head -n 1 |
    awk '{print $2}' || true)"
  printf '%s %s %s\n' "${state:-NO_SUMMARY}" "${sim_s:--}" \
    "$(awk -v a="$start_s" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}')" >"$dir/worker.txt"
  exit 0
fi

n=200
seed=1
jobs="$(nproc)"
out=""
build=1
cue_effect=0
crowd=0
while [ $# -gt 0 ]; do
  case "$1" in
    --n | --seed | -j | --out | --profile) coopnav_need_value population.sh "$1" $# ;;&
    --n) n="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    -j) jobs="$2"; shift 2 ;;
    -j*) jobs="${1#-j}"; shift ;;
    --out) out="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    --tracker-noise)
      export COOPNAV_DAEMON_ARGS_world_sim="${COOPNAV_DAEMON_ARGS_world_sim:-} \
--set tracker.position_sigma_m=0.05 --set tracker.miss_probability=0.05 --set tracker.id_switches=1"
      shift ;;
    --goals-withheld)
      export COOPNAV_DAEMON_ARGS_world_sim="${COOPNAV_DAEMON_ARGS_world_sim:-} \
--set publish_human_goals=false"
      shift ;;
    --realistic-timing)
      export COOPNAV_DAEMON_ARGS_world_sim="${COOPNAV_DAEMON_ARGS_world_sim:-} \
--set avoidance_timing=realistic"
      shift ;;
    --profile) export COOPNAV_PROFILE="$2"; shift 2 ;;
    --cue-effect) cue_effect=1; shift ;;
    --crowd) crowd=1; shift ;;
    -h|--help) sed -n '2,29p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "population.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "population.sh: -j needs a positive integer" >&2; exit 2; }
[[ "$n" =~ ^[0-9]+$ ]] || { echo "population.sh: --n needs a count, not '$n'" >&2; exit 2; }
[[ "$seed" =~ ^[0-9]+$ ]] || { echo "population.sh: --seed needs an integer, not '$seed'" >&2; exit 2; }
# Each run is seven processes stepping in lockstep: past a few runs per core they only wait on
# each other, every run slows towards COOPNAV_POP_RUN_TIMEOUT_S and fails; and each slot takes a
# udpm port of its own above COOPNAV_POP_PORT_BASE.
max_jobs=$((4 * $(nproc)))
if [ "${#jobs}" -gt 6 ] || [ "$jobs" -gt "$max_jobs" ]; then
  echo "population.sh: -j $jobs capped to $max_jobs (4 runs per core)" >&2
  jobs=$max_jobs
fi
case "${COOPNAV_PROFILE:-paper}" in
  paper | calibrated | forecast) ;;
  *) echo "population.sh: --profile must be paper, calibrated or forecast, not '$COOPNAV_PROFILE'" >&2; exit 2 ;;
esac
if [ "$cue_effect" -eq 1 ] && [ "$crowd" -eq 1 ]; then
  echo "population.sh: --cue-effect and --crowd do not go together" >&2
  exit 2
fi

if [ "$build" -eq 1 ]; then
  coopnav_install_deps
  coopnav_build
fi
coopnav_ensure_multicast

# A daemon older than its config (keys added since it was built) would only fail at each run.
for d in "${COOPNAV_DAEMONS[@]}" world_sim; do
  if ! errors="$("$(coopnav_bin "$d")" -c "$COOPNAV_ROOT/config/$d.yaml" --print-config 2>&1 >/dev/null)"; then
    echo "population.sh: $d rejects config/$d.yaml (rebuild $COOPNAV_BUILD_DIR?):" >&2
    echo "$errors" >&2
    exit 2
  fi
done
if [ "$cue_effect" -eq 1 ] && ! errors="$("$(coopnav_bin dialogue_manager)" \
    -c "$COOPNAV_ROOT/config/dialogue_manager.yaml" --set muted=true --print-config 2>&1 >/dev/null)"; then
  echo "population.sh: dialogue_manager does not take --set muted=true (rebuild?):" >&2
  echo "$errors" >&2
  exit 2
fi

gen_args=()
if [ "$cue_effect" -eq 1 ]; then
  gen_args=(--behaviour responsive --cue-effect)
  out="${out:-$COOPNAV_ROOT/runs/population-$seed-cue}"
fi
if [ "$crowd" -eq 1 ]; then
  gen_args=(--crowd)
  out="${out:-$COOPNAV_ROOT/runs/population-$seed-crowd}"
fi
out="${out:-$COOPNAV_ROOT/runs/population-$seed}"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
"$pop" generate --n "$n" --seed "$seed" --out "$out" --maps-dir "$COOPNAV_ROOT/config/maps" \
  "${gen_args[@]}"

port_base="${COOPNAV_POP_PORT_BASE:-7400}"
timeout_s="${COOPNAV_POP_RUN_TIMEOUT_S:-900}"
declare -A slot_of=()  # worker pid -> slot (its port offset)
declare -A name_of=()  # worker pid -> run name
free_slots=()
for ((s = 0; s < jobs; s++)); do free_slots+=("$s"); done
stop_workers() {
  local p
  for p in "${!slot_of[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
coopnav_trap 'stop_workers; exit 130' INT TERM

# Progress: one line per finished run (name, final state, simulated and wall time of the run,
# runs done / all, ETA from the mean wall time per finished run at this JOBS); on a terminal the
# line is rewritten in place, piped every line stays.
done_runs=0
progress() {  # NAME
  local name="$1" state="NO_SUMMARY" sim="-" wall="-" now eta line
  if [ -f "$out/runs/$name/worker.txt" ]; then read -r state sim wall <"$out/runs/$name/worker.txt"; fi
  done_runs=$((done_runs + 1))
  now=$(date +%s.%N)
  eta="$(awk -v a="$start_s" -v b="$now" -v d="$done_runs" -v n="${#lines[@]}" 'BEGIN{
    s = (b - a) / d * (n - d); printf "%dm%02ds", int(s / 60), int(s) % 60 }')"
  [ "$sim" = "-" ] || sim="$(printf '%.1f s' "$sim")"
  line="$(printf '[%d/%d] %-16s %-19s sim %-8s wall %6s s  ETA %s' "$done_runs" "${#lines[@]}" \
    "$name" "$state" "$sim" "$wall" "$eta")"
  if [ -t 1 ]; then printf '\r%s\033[K' "$line"; else echo "$line"; fi
}

reap() {
  local p
  for p in "${!slot_of[@]}"; do
    if ! kill -0 "$p" 2>/dev/null; then
      wait "$p" 2>/dev/null || true
      free_slots+=("${slot_of[$p]}")
      unset "slot_of[$p]"
      progress "${name_of[$p]}"
      unset "name_of[$p]"
    fi
  done
}

mapfile -t lines <"$out/jobs.txt"
echo "population: ${#lines[@]} runs, $jobs at a time, in $out"
start_s=$(date +%s.%N)
for line in "${lines[@]}"; do
  # name<TAB>scenario[<TAB>muted]: a muted twin (--cue-effect) runs its encounter's file with the
  # dialogue manager deciding and acting as usual but saying nothing.
  IFS=$'\t' read -r name scenario mode <<<"$line"
  scenario="$out/$scenario"
  while [ "${#free_slots[@]}" -eq 0 ]; do
    wait -n 2>/dev/null || true
    reap
  done
  slot="${free_slots[0]}"
  free_slots=("${free_slots[@]:1}")
  if [ "${mode:-}" = muted ]; then
    COOPNAV_DAEMON_ARGS_dialogue_manager="${COOPNAV_DAEMON_ARGS_dialogue_manager:-} --set muted=true" \
      timeout -k 20 "$timeout_s" bash "$0" --worker "$scenario" "$out/runs/$name" \
      "$((port_base + slot))" &
  else
    timeout -k 20 "$timeout_s" bash "$0" --worker "$scenario" "$out/runs/$name" \
      "$((port_base + slot))" &
  fi
  slot_of[$!]="$slot"
  name_of[$!]="$name"
done
while [ "${#slot_of[@]}" -gt 0 ]; do
  wait -n 2>/dev/null || true
  reap
done
if [ -t 1 ]; then echo; fi
wall_s="$(awk -v a="$start_s" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}')"
echo "runs ${#lines[@]} jobs $jobs wall_s $wall_s" >"$out/timing.txt"
echo "population: ${#lines[@]} runs in $wall_s s wall with -j $jobs"

rc=0
"$pop" aggregate --dir "$out" || rc=$?
echo "population: $out/population.txt, $out/population.json"
exit "$rc"
