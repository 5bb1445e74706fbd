#!/usr/bin/env bash
# libFuzzer targets of test/fuzz (test/fuzz/README.md). Builds them into build-fuzz/ (clang-14,
# ASan + UBSan + coverage) and runs each on its committed corpus.
#
#   scripts/fuzz.sh --short [TARGET...]  CI: each target for COOPNAV_FUZZ_SHORT_S seconds (15),
#                                        COOPNAV_FUZZ_JOBS (nproc) targets at a time
#   scripts/fuzz.sh --long  [TARGET...]  each target for COOPNAV_FUZZ_LONG_RUNS executions (10M),
#                                        or COOPNAV_FUZZ_LONG_S seconds if set and reached first
#   scripts/fuzz.sh --seed               regenerate the generated seeds and copy the repo's configs,
#                                        scenarios and maps into test/fuzz/corpus/
#   scripts/fuzz.sh --build              build only
#
# COOPNAV_FUZZ_WORKERS=N (--long, default 1): a campaign of N fuzzer processes on the target's one
# corpus directory, as libFuzzer's -jobs runs them, each for ceil(runs / N) executions; their
# counts add up (the campaign's total is printed).
#
# COOPNAV_FUZZ_SKIP_BUILD=1 runs the fuzzers already in build-fuzz/ (a long campaign goes on while
# the tree is edited and rebuilt by hand; two builds in one directory would clash).
#
# Any finding (crash, sanitizer report, leak, timeout, out-of-memory) fails the run; libFuzzer
# writes the input to build-fuzz/findings/<target>/ (reproduce: README.md). New corpus entries go to
# build-fuzz/corpus/<target>/, never into the committed seeds.
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

FUZZ_BUILD_DIR="${COOPNAV_FUZZ_BUILD_DIR:-$COOPNAV_ROOT/build-fuzz}"
FUZZ_SRC="$COOPNAV_ROOT/test/fuzz"
SHORT_S="${COOPNAV_FUZZ_SHORT_S:-15}"
LONG_RUNS="${COOPNAV_FUZZ_LONG_RUNS:-10000000}"
# Optional wall-time cap of each --long target [s] (0 = none): whichever of runs / time comes first.
LONG_S="${COOPNAV_FUZZ_LONG_S:-0}"
# Limits of every run: a single input may take at most TIMEOUT_S seconds and RSS_MB of memory; an
# input past either is a finding (a hostile file or message must not hang or exhaust a daemon).
TIMEOUT_S="${COOPNAV_FUZZ_TIMEOUT_S:-10}"
RSS_MB="${COOPNAV_FUZZ_RSS_MB:-2048}"
MAX_LEN="${COOPNAV_FUZZ_MAX_LEN:-8192}"
WORKERS="${COOPNAV_FUZZ_WORKERS:-1}"

NICE=()
INTERRUPTED=0
# The daemons and the world in config/system.yaml's start order (one LCM fuzzer each).
mapfile -t DAEMONS < <("$COOPNAV_ROOT/scripts/coopnav" system daemons --with-world)
TARGETS=("${DAEMONS[@]/#/fuzz_lcm_}" fuzz_lcm_sequence fuzz_run_log fuzz_map_yaml fuzz_map_pgm
  fuzz_map_bt fuzz_config fuzz_scenario)

fuzz_build() {
  command -v clang++-14 >/dev/null || {
    echo "fuzz: clang++-14 missing (Debian: clang-14 libclang-rt-14-dev)" >&2
    exit 1
  }
  # Tests and benchmarks stay out: only the fuzz targets and what they link are built.
  # -O1 with line tables: the usual fuzzing trade-off (fast enough to run, stacks with file:line),
  # and it compiles much faster than -O2 -g on CI's two cores.
  cmake -S "$COOPNAV_ROOT" -B "$FUZZ_BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=None \
    -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" -DCMAKE_CXX_COMPILER=clang++-14 -DCOOPNAV_FUZZ=ON -DCOOPNAV_BUILD_TESTS=OFF \
    -DCOOPNAV_BUILD_BENCH=OFF >/dev/null
  cmake --build "$FUZZ_BUILD_DIR" --target coopnav_fuzz -j"${COOPNAV_FUZZ_JOBS:-$(nproc)}"
}

fuzz_seed() {
  local c="$FUZZ_SRC/corpus"
  "$FUZZ_BUILD_DIR/test/fuzz/fuzz_seed_gen" "$c"
  # Configs: selector byte (the daemon: fuzz_config.cpp numbers them in system.yaml's start order,
  # the world last) + the repo's YAML without its comment and blank lines (every key and value
  # kept, a first comment names the file). The files are 75-95 % comments (band_source.yaml:
  # 10 KB, above fuzz_config's -max_len of 4096); one seed keeps them all, so the parser's comment
  # paths stay seeded (test/fuzz/README.md).
  local i=0 d
  mkdir -p "$c/fuzz_config"
  # Only the copies are replaced: regression_*.yaml are crash inputs kept by hand.
  find "$c/fuzz_config" -name '*.yaml' ! -name 'regression_*' -delete
  for d in "${DAEMONS[@]}"; do
    { printf "\\$(printf '%03o' "$i")"; echo "# config/$d.yaml without its comment lines"
      grep -v -E '^[[:space:]]*(#|$)' "$COOPNAV_ROOT/config/$d.yaml"; } >"$c/fuzz_config/$d.yaml"
    i=$((i + 1))
  done
  { printf '\000'; cat "$COOPNAV_ROOT/config/obstacle_distance_server.yaml"; } \
    >"$c/fuzz_config/obstacle_distance_server_commented.yaml"
  # Scenarios: the repo's, with a map resolution_m finer than 0.1 m coarsened to 0.1 m (noted in
  # a first comment): the paper's 6 m corridors at 0.05 m are 84 000 cells, ~90 ms per execution
  # in the instrumented build, 3x the same scenario at 0.1 m. Everything else is kept as it is.
  mkdir -p "$c/fuzz_scenario"
  find "$c/fuzz_scenario" -name '*.yaml' ! -name 'regression_*' -delete
  local s
  coarse_scenario() {
    awk -v src="$1" '
      BEGIN { n = 0 }
      { lines[n++] = $0 }
      /^[[:space:]]+resolution_m:[[:space:]]*[0-9.]+[[:space:]]*$/ {
        split($0, kv, ":"); v = kv[2] + 0
        if (v < 0.1) { sub(/:[[:space:]]*[0-9.]+/, ": 0.1", lines[n - 1]); from = v }
      }
      END {
        if (from != "") print "# fuzz seed: " src ", map resolution_m " from " -> 0.1 m"
        for (k = 0; k < n; ++k) print lines[k]
      }' "$COOPNAV_ROOT/$1"
  }
  for s in "$COOPNAV_ROOT"/config/scenarios/*.yaml; do
    coarse_scenario "config/scenarios/$(basename "$s")" >"$c/fuzz_scenario/$(basename "$s")"
  done
  for s in "$COOPNAV_ROOT"/test/data/scenarios/*.yaml; do
    coarse_scenario "test/data/scenarios/$(basename "$s")" >"$c/fuzz_scenario/test_$(basename "$s")"
  done
  cp "$COOPNAV_ROOT"/config/scenarios/narrow_minimal.yaml "$c/fuzz_map_yaml/scenario_narrow.yaml"
}

# run_target NAME ARGS...: runs one fuzzer on its committed corpus; non-zero on a finding.
run_target() {
  local name="$1"
  shift
  local bin="$FUZZ_BUILD_DIR/test/fuzz/$name"
  local work="$FUZZ_BUILD_DIR/corpus/$name" findings="$FUZZ_BUILD_DIR/findings/$name"
  local dict="$FUZZ_SRC/$name.dict" extra=()
  mkdir -p "$work" "$findings"
  [ -f "$dict" ] && extra+=(-dict="$dict")
  # <target>.options: that target's own limits, after (and so over) the defaults.
  if [ -f "$FUZZ_SRC/$name.options" ]; then
    local opts
    read -r -a opts <"$FUZZ_SRC/$name.options"
    extra+=("${opts[@]}")
  fi
  echo "fuzz: $name $*"
  # New inputs go to the work corpus (first directory); the committed seeds are only read.
  local fuzzer=("$bin" -timeout="$TIMEOUT_S" -rss_limit_mb="$RSS_MB" -max_len="$MAX_LEN"
    -artifact_prefix="$findings/" -print_final_stats=1 "${extra[@]}")
  local corpora=("$work" "$FUZZ_SRC/corpus/$name")
  local rc
  if [ ${#NICE[@]} -gt 0 ]; then
    # A long run's fuzzers get a session of their own and that session's autogroup the lowest
    # priority. Linux's autogroup scheduling (sched_autogroup_enabled, on in Debian's kernels)
    # shares the CPU between sessions first and applies nice only within a session: a fuzzer at
    # nice 19 beside a build or a benchmark started from another terminal took half their CPU
    # (bench_band, 1 human: p99 29 ms with the fuzzers' autogroup at 0, 9-14 ms at 19). Its own
    # session leaves the caller's untouched; INT / TERM are passed on, as Ctrl-C would be. (A
    # script's background job is no process group leader, so setsid does not fork: $! is the
    # fuzzer.) Worker w of a campaign logs to log-w<w>.txt, and log.txt gathers their stats.
    local w pids=() logs=()
    local a runs_arg=() other=()
    for a in "$@"; do
      case "$a" in
        -runs=*) runs_arg=("-runs=$(((${a#-runs=} + WORKERS - 1) / WORKERS))") ;;
        *) other+=("$a") ;;
      esac
    done
    for ((w = 1; w <= WORKERS; ++w)); do
      local log="$findings/log.txt"
      [ "$WORKERS" -gt 1 ] && log="$findings/log-w$w.txt"
      logs+=("$log")
      # shellcheck disable=SC2016 # expanded by the inner sh
      (cd "$findings" && exec setsid sh -c 'echo 19 >/proc/self/autogroup 2>/dev/null; exec "$@"' \
        fuzz "${NICE[@]}" "${fuzzer[@]}" "${other[@]}" ${runs_arg[@]+"${runs_arg[@]}"} \
        "${corpora[@]}") >"$log" 2>&1 &
      pids+=($!)
    done
    coopnav_trap 'INTERRUPTED=1; kill -INT "${pids[@]}" 2>/dev/null' INT TERM
    rc=0
    local pid r
    for pid in "${pids[@]}"; do
      # A signal interrupts a wait; the fuzzers then print their stats and exit.
      while :; do
        wait "$pid"
        r=$?
        kill -0 "$pid" 2>/dev/null || break
      done
      [ $r -ne 0 ] && rc=$r
    done
    trap - INT TERM
    if [ "$WORKERS" -gt 1 ]; then
      {
        for w in "${!logs[@]}"; do
          echo "== worker $((w + 1)): ${logs[$w]}"
          grep -a -E '^(stat::|==ERROR|ERROR: libFuzzer|SUMMARY)' "${logs[$w]}"
        done
        awk -F: '/^stat::number_of_executed_units/ { n += $NF }
          END { printf "stat::number_of_executed_units: %d (campaign of %d workers)\n", n, w }' \
          w="$WORKERS" "${logs[@]}"
      } >"$findings/log.txt"
    fi
  else
    (cd "$findings" && "${fuzzer[@]}" "$@" "${corpora[@]}") >"$findings/log.txt" 2>&1
    rc=$?
  fi
  grep -a -E '^(#[0-9]+.*DONE|stat::number_of_executed_units|stat::average_exec_per_sec|stat::peak_rss_mb)' \
    "$findings/log.txt" | sed "s/^/fuzz:   /"
  if [ "$INTERRUPTED" = 1 ]; then
    echo "fuzz: $name interrupted (stopped by a signal, no finding); log: $findings/log.txt" >&2
    exit 130
  fi
  if [ $rc -ne 0 ]; then
    echo "fuzz: $name FAILED (rc $rc); log: $findings/log.txt" >&2
    grep -a -E '==ERROR|ERROR: libFuzzer|SUMMARY|invariant|Test unit written|runtime error|terminate' \
      "$findings/log.txt" | head -20 >&2
  fi
  return $rc
}

# Targets left out of --short (CI) while they have an open finding (none now: fuzz_scenario's
# non-scalar-key abort in world_sim's scenario Reader is fixed and tested).
SHORT_SKIP=()

mode="${1:---short}"
[ $# -gt 0 ] && shift
selected=("$@")
if [ ${#selected[@]} -eq 0 ]; then
  for t in "${TARGETS[@]}"; do
    if [ "$mode" = --short ] && [[ " ${SHORT_SKIP[*]} " == *" $t "* ]]; then
      echo "fuzz: $t skipped in --short (open finding, see test/fuzz/README.md)"
      continue
    fi
    selected+=("$t")
  done
fi

case "$mode" in
  --build)
    fuzz_build
    ;;
  --seed)
    fuzz_build
    fuzz_seed
    ;;
  --short | --long)
    [ "${COOPNAV_FUZZ_SKIP_BUILD:-0}" = 1 ] || fuzz_build
    failed=()
    if [ "$mode" = --short ]; then
      # The short runs are independent single-threaded fuzzers: one per core at a time, each
      # with its output kept apart and printed in target order when all have ended.
      out=$(mktemp -d)
      coopnav_trap 'rm -rf "$out"' EXIT
      for t in "${selected[@]}"; do
        while [ "$(jobs -rp | wc -l)" -ge "${COOPNAV_FUZZ_JOBS:-$(nproc)}" ]; do wait -n || :; done
        (
          set +e
          run_target "$t" -max_total_time="$SHORT_S" >"$out/$t.log" 2>&1
          echo $? >"$out/$t.rc"
        ) &
      done
      wait
      for t in "${selected[@]}"; do
        cat "$out/$t.log"
        [ "$(cat "$out/$t.rc" 2>/dev/null || echo 1)" -ne 0 ] && failed+=("$t")
      done
    else
      # Long runs share the machine: lowest priority, one target at a time, COOPNAV_FUZZ_WORKERS
      # processes each.
      # Never pause one (SIGSTOP, e.g. for a benchmark): -timeout is wall time, so the input in
      # progress when it resumes is reported as a timeout (fuzz_run_log: a 56 ms input, after
      # a 60 s pause, ended a 10M run at 4.3M).
      NICE=(nice -n 19)
      # No allocation stacks in ASan's reports of a long run: their depot only grows (yaml-cpp's
      # recursion makes ever new stacks) until storing one is a third of the time (fuzz_config:
      # 2750 -> 600 exec/s after 17 min). A finding is re-run with full stacks to report it.
      export ASAN_OPTIONS="${ASAN_OPTIONS:-malloc_context_size=0}"
      for t in "${selected[@]}"; do
        set +e
        run_target "$t" -runs="$LONG_RUNS" -max_total_time="$LONG_S"
        rc=$?
        set -e
        [ $rc -ne 0 ] && failed+=("$t")
      done
    fi
    if [ ${#failed[@]} -gt 0 ]; then
      echo "fuzz: findings in ${failed[*]} (inputs in $FUZZ_BUILD_DIR/findings/)" >&2
      exit 1
    fi
    echo "fuzz: ${#selected[@]} targets, no finding"
    ;;
  *)
    sed -n '2,21p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
