#!/usr/bin/env bash
# The main job: runs the paper's experiment (§III). For each scenario it starts the daemons as
# separate processes on a host-local LCM port of its own, runs the world simulator in lockstep,
# records an LCM log, and prints the transcript (what the robot said and did, when, and why);
# then the CM table beside the paper's Table I. Writes runs/<timestamp>/ and runs/latest.
#
#   scripts/run.sh [--out DIR] [--no-build] [--profile paper|calibrated|forecast] [--speech]
#                  [scenario.yaml ...]
#   (default scenarios: config/scenarios/{open,narrow}_{facilitating,minimal}.yaml; --profile:
#   the config files the daemons run, default paper: calibrated = config/path_assessor_
#   calibrated.yaml, forecast = config/dialogue_manager_forecast.yaml (scripts/scenario.sh);
#   --speech: espeak-ng says each utterance into DIR/<scenario>/speech/*.wav, and the dialogue
#   manager plans with the durations it measures; DIR without spaces)
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
source "$COOPNAV_ROOT/scripts/scenario.sh"

out=""
build=1
speech=0
scenarios=()
while [ $# -gt 0 ]; do
  case "$1" in
    --out | --profile) coopnav_need_value run.sh "$1" $# ;;&
    --out) out="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    --profile) export COOPNAV_PROFILE="$2"; shift 2 ;;
    --speech) speech=1; shift ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "run.sh: unknown option $1" >&2; exit 2 ;;
    *) scenarios+=("$1"); shift ;;
  esac
done
if [ "${#scenarios[@]}" -eq 0 ]; then
  for s in open_facilitating open_minimal narrow_facilitating narrow_minimal; do
    scenarios+=("$COOPNAV_ROOT/config/scenarios/$s.yaml")
  done
fi
for s in "${scenarios[@]}"; do
  [ -f "$s" ] || { echo "run.sh: no scenario file '$s'" >&2; exit 2; }
done
case "${COOPNAV_PROFILE:-paper}" in
  paper | calibrated | forecast) ;;
  *) echo "run.sh: --profile must be paper, calibrated or forecast, not '$COOPNAV_PROFILE'" >&2; exit 2 ;;
esac

if [ "$build" -eq 1 ]; then
  coopnav_install_deps
  coopnav_build
fi
coopnav_ensure_multicast

if [ -z "$out" ]; then
  stamp="$(date -u +%Y%m%d-%H%M%S)"
  out="$COOPNAV_ROOT/runs/$stamp"
  mkdir -p "$out"
  ln -sfn "$stamp" "$COOPNAV_ROOT/runs/latest"
else
  mkdir -p "$out"
fi
out="$(cd "$out" && pwd)"
ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"
# Port base: CI runs several suites at once; each scenario gets its own port from here.
port="${COOPNAV_RUN_PORT_BASE:-7670}"

coopnav_trap coopnav_stop_all EXIT
coopnav_trap 'coopnav_stop_all; exit 130' INT TERM

summaries=()
ended_badly=()
failed=0
dm_args="${COOPNAV_DAEMON_ARGS_dialogue_manager:-}"  # --speech adds to these per scenario
coopnav_progress_start "${#scenarios[@]}"
for scenario in "${scenarios[@]}"; do
  scenario="$(cd "$(dirname "$scenario")" && pwd)/$(basename "$scenario")"
  name="$(basename "$scenario" .yaml)"
  dir="$out/$name"
  echo "== $name  ($scenario)"
  coopnav_progress_run "$name"
  rc=0
  if [ "$speech" -eq 1 ]; then
    export COOPNAV_DAEMON_ARGS_dialogue_manager="$dm_args --set speech.enabled=true \
--set speech.wav_dir=$dir/speech"
  fi
  coopnav_run_scenario "$scenario" "$dir" "$port" || rc=$?
  port=$((port + 1))
  if [ "$rc" -ne 0 ]; then
    coopnav_progress_end /dev/null
    echo "run.sh: the run failed (exit $rc) for $name; see $dir/*.log" >&2
    tail -5 "$dir/world_sim.log" >&2 || true
    failed=1
    continue
  fi
  "$ctl" transcript "$dir/$name.lcm" --scenario "$name" >"$dir/transcript.txt"
  coopnav_progress_end "$dir/transcript.txt"
  cat "$dir/transcript.txt"
  "$ctl" summarize "$dir/$name.lcm" --scenario "$name" --out "$dir/summary.json"
  "$ctl" figures "$dir/$name.lcm" --scenario "$name" --out-dir "$dir"
  echo "   view this run: $(coopnav_bin viewer) --log $dir/$name.lcm  then open http://127.0.0.1:8088/"
  summaries+=("$dir/summary.json")
  if ! reason="$(coopnav_run_outcome_failure "$dir/summary.json")"; then
    echo "run.sh: $name: $reason" >&2
    ended_badly+=("$name: $reason")
  fi
  echo
done

if [ "${#summaries[@]}" -gt 0 ]; then
  "$ctl" merge-summaries "$out/summary.json" "${summaries[@]}"
  "$ctl" cm-table "$out/summary.json" | tee "$out/cm_table.txt"
  "$ctl" summary-figures "$out/summary.json" --out-dir "$out"
  echo "run directory: $out (logs, transcripts, summary.json, figures *.svg)"
fi
# Exit status: 0 every run reached every goal without contact; 1 a run failed (no log, a daemon
# died); 3 a run ended in a contact, a standstill or the time limit (each reason on stderr, read
# from its summary.json): a safe run that does not progress is a failure too.
if [ "$failed" -eq 0 ] && [ "${#ended_badly[@]}" -gt 0 ]; then
  printf 'run.sh: %s\n' "${ended_badly[@]}" >&2
  failed=3
fi
exit "$failed"
