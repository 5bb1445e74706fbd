#!/usr/bin/env bash
# A population of head-on corridor (or crowd) encounters (docs/population.md): generates N
# scenario files from a seed (tools/population), runs them JOBS at a time, each on a udpm port of
# its own and in a folder of its own, plus one run without humans per corridor layout (the
# time-to-goal baseline), and writes DIR/population.json and DIR/population.txt. Exit non-zero:
# 1 a contact with the robot at fault; 4 a failed dialogue check (words to someone not crossed, a
# contradiction, a group told twice, unaddressed among several); 5 a run ended in any contact, a
# standstill, the time limit or a mutual wait over 10 s (why on stderr); 3 a run left no summary;
# muted twins included; 2 bad arguments or files. A line per finished run says where it stands.
#
#   scripts/population.sh [--n N] [--seed S] [-j JOBS] [--out DIR] [--no-build]
#                         [--tracker-noise] [--goals-withheld] [--profile paper|calibrated]
#                         [--cue-effect | --crowd] [--slurm ...]
#
# The entry point of `scripts/coopnav population` (tools/exp/coopnav_exp/population.py: the
# options, the job pool, Slurm); `scripts/population.sh --help` lists every option.

# FALLBACK until coopnav_exp.run.run_one is in the tree (population.py
# run_one_via_population_sh_fallback calls it; the integrator removes both): one run,
#   population.sh --worker SCENARIO RUN_DIR PORT
if [ "${1:-}" = "--worker" ]; then
  source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
  source "$COOPNAV_ROOT/scripts/scenario.sh"
  ctl="$COOPNAV_BUILD_DIR/tools/coopnav_ctl"
  coopnav_trap coopnav_stop_all EXIT
  coopnav_trap 'coopnav_stop_all; exit 143' INT TERM
  scenario="$2" dir="$3" port="$4"
  name="$(basename "$scenario" .yaml)"  # a muted twin runs its encounter's file: same name
  rm -rf "$dir"
  mkdir -p "$dir"
  rc=0
  coopnav_run_scenario "$scenario" "$dir" "$port" || rc=$?
  echo "$rc" >"$dir/world_sim.exit"
  if [ -f "$dir/$name.lcm" ]; then
    "$ctl" summarize "$dir/$name.lcm" --scenario "$name" --out "$dir/summary.json" \
      >"$dir/summarize.log" 2>&1 || true
  fi
  exit 0
fi

exec "$(dirname "${BASH_SOURCE[0]}")/coopnav" population "$@"
