# Shared by the scripts: repository paths, dependency install, build, LCM route check.
# Sourced, not executed.
set -euo pipefail

COOPNAV_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:-$COOPNAV_ROOT/build}"

# Debian 12 packages: toolchain, LCM (C/C++, tools, Java with its window toolkit for lcm-spy),
# libraries (cpp-httplib: the viewer), test tools (Xvfb: lcm-spy in a real display, e2e_spy_test;
# Chromium: the viewer's page, headless, e2e_viewer_test), clang with its libFuzzer /
# sanitizer runtimes (scripts/fuzz.sh), clang-format and clang-tidy (scripts/lint.sh).
COOPNAV_DEBS=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  liblcm-dev liblcm-bin liblcm-java libglib2.0-dev default-jdk-headless default-jre libjchart2d-java
  libeigen3-dev liboctomap-dev libdynamicedt3d-dev libspdlog-dev libyaml-cpp-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev libceres-dev nlohmann-json3-dev libcpp-httplib-dev
  iproute2 procps python3 espeak-ng sox xvfb fonts-dejavu-core chromium
  python3-yaml python3-numpy python3-matplotlib python3-pytest  # tools/exp (figures: matplotlib)
  clang-14 libclang-rt-14-dev clang-format clang-tidy
  cyclonedds-dev cyclonedds-tools  # the ROS 2 bridge (daemons/ros2_bridge): Cyclone DDS + idlc
  slurm-wlm munge  # populations on Slurm (docs/slurm.md) and its single-node test (test_slurm.py)
)

coopnav_sudo() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

coopnav_install_deps() {
  local missing=()
  for p in "${COOPNAV_DEBS[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep "ok installed" >/dev/null || missing+=("$p")
  done
  if [ "${#missing[@]}" -gt 0 ]; then
    echo "coopnav: installing ${#missing[@]} Debian packages: ${missing[*]}"
    coopnav_sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq
    coopnav_sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      "${missing[@]}"
  fi
}

coopnav_build() {
  local extra=()
  if [ "${CI:-}" = "true" ]; then extra+=(-DCOOPNAV_WERROR=ON); fi
  cmake -S "$COOPNAV_ROOT" -B "$COOPNAV_BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "${extra[@]}" "$@" >/dev/null
  # COOPNAV_BUILD_TARGETS (space-separated): build only these (scripts/sanitizers.sh), else all.
  local targets=()
  if [ -n "${COOPNAV_BUILD_TARGETS:-}" ]; then
    read -r -a targets <<<"$COOPNAV_BUILD_TARGETS"
    targets=(--target "${targets[@]}")
  fi
  cmake --build "$COOPNAV_BUILD_DIR" -j"$(nproc)" "${targets[@]}"
}

# LCM's udpm needs a multicast route; a minimal machine (or container) may have none on lo.
coopnav_ensure_multicast() {
  # LCM asks for 4 MB receive buffers (recv_buf_size in our URLs), but the kernel caps them at
  # net.core.rmem_max (often 208 KB): a burst of bands then loses datagrams (measured with 1 MB
  # messages: 77 % lost at the default buffer, none at 4 MB). Raise the cap when we may;
  # elsewhere it stays a warning.
  local rmem
  rmem=$(sysctl -n net.core.rmem_max 2>/dev/null || echo 0)
  if [ "$rmem" -lt 8388608 ]; then
    coopnav_sudo sysctl -q -w net.core.rmem_max=8388608 >/dev/null 2>&1 ||
      echo "coopnav: could not raise net.core.rmem_max ($rmem); LCM may drop bursts" >&2
  fi
  # No grep -q: it exits at the first match, ip gets SIGPIPE, and pipefail calls that a failure.
  if ip route show 2>/dev/null | grep -E '^(224\.0\.0\.0/4|default)' >/dev/null; then return 0; fi
  echo "coopnav: no multicast route; adding 224.0.0.0/4 on lo" >&2
  coopnav_sudo ip link set lo up || true
  coopnav_sudo ip link set lo multicast on || true
  coopnav_sudo ip route add 224.0.0.0/4 dev lo || true
}

coopnav_bin() { echo "$COOPNAV_BUILD_DIR/daemons/$1/coopnav_$1"; }

# Background processes of a script (daemons, logger): started with their output in a log file,
# stopped together (SIGTERM, then waited for, so the logger flushes and daemons exit cleanly).
COOPNAV_PIDS=()
# coopnav_wait_ready_watching PIDMAP LOGDIR WAIT_CMD...: runs WAIT_CMD (a `coopnav_ctl
# wait-ready ...`) while watching the daemons of the associative array named PIDMAP (name ->
# pid): one that dies meanwhile (a bad config, map or scenario) is reported at once with its exit
# status and the end of LOGDIR/<name>.log, instead of after the wait's whole timeout. Returns
# WAIT_CMD's status, or 1 when a daemon died.
coopnav_wait_ready_watching() {
  local -n _cn_w_pids="$1"
  local logdir="$2" waiter dead="" d drc=0 wrc=0
  shift 2
  "$@" &
  waiter=$!
  while [ -z "$dead" ] && kill -0 "$waiter" 2>/dev/null; do
    for d in "${!_cn_w_pids[@]}"; do
      kill -0 "${_cn_w_pids[$d]}" 2>/dev/null || { dead="$d"; break; }
    done
    [ -n "$dead" ] || sleep 0.1
  done
  if [ -n "$dead" ]; then
    kill "$waiter" 2>/dev/null || true
    wait "$waiter" 2>/dev/null || true
    wait "${_cn_w_pids[$dead]}" 2>/dev/null || drc=$?
    echo "coopnav: $dead exited at start (status $drc); the end of $logdir/$dead.log:" >&2
    tail -n 10 "$logdir/$dead.log" | sed "s/^/  $dead: /" >&2
    return 1
  fi
  wait "$waiter" || wrc=$?
  return "$wrc"
}

# coopnav_need_value SCRIPT OPTION ARGC: in a script's option loop, before reading "$2": an
# option given last without its value is a usage error that names it (under `set -u`, bash would
# only say "$2: unbound variable").
coopnav_need_value() {
  if [ "$3" -lt 2 ]; then
    echo "$1: $2 needs a value (--help)" >&2
    exit 2
  fi
}

coopnav_spawn() {  # coopnav_spawn LOGFILE CMD ARGS...
  local log="$1"
  shift
  "$@" >"$log" 2>&1 &
  COOPNAV_PIDS+=($!)
}
# coopnav_record FILE REGEX LOGFILE: the recorder of a run in the background (tools/record: no
# message dropped when it is starved of CPU, unlike lcm-logger 1.3.1's queue of 30).
coopnav_record() {
  coopnav_spawn "$3" "$COOPNAV_BUILD_DIR/tools/coopnav_record" -f -c "$2" \
    --lcm-url "$LCM_DEFAULT_URL" "$1"
}

# coopnav_wait_recorded FILE: the last messages reach the recorder; on a loaded machine it may lag
# behind the run. Returns once the file stopped growing for 0.3 s (at most ~5 s).
coopnav_wait_recorded() {
  local size=-1 now_size i
  for i in $(seq 1 16); do
    sleep 0.3
    now_size=$(stat -c %s "$1" 2>/dev/null || echo 0)
    [ "$now_size" = "$size" ] && return 0
    size=$now_size
  done
}

# coopnav_trap CMD SIGNAL...: `trap CMD SIGNAL...` that only the shell setting it runs; in any
# other shell the trap just exits. Bash (5.2) runs a parent's traps in a subshell that a signal
# reaches in the instant after fork, before the child has reset the handlers it inherited: a
# watchdog or ticker stopped with SIGTERM then ran its parent's EXIT trap, which stopped every
# daemon with SIGKILL and removed the run's files under the parent. The guard reads the pid from
# /proc/self: in that instant $BASHPID can still hold the parent's. Every script sets its traps
# with this (test/arch_rules.sh checks).
coopnav_trap() {
  local cmd="$1"
  shift
  # shellcheck disable=SC2064 # this shell's pid, fixed now
  trap "read -r _cn_trap_pid _ </proc/self/stat; if [ \"\$_cn_trap_pid\" != $BASHPID ]; then exit 1; fi
$cmd" "$@"
}

coopnav_stop_all() {
  local p
  for p in "${COOPNAV_PIDS[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  for p in "${COOPNAV_PIDS[@]}"; do wait "$p" 2>/dev/null || true; done
  COOPNAV_PIDS=()
}

# Progress of a job of several runs (run.sh, faults.sh; population.sh has its own): one line per
# finished run with the simulated time it covered, its outcome, its wall time and the job's ETA
# (mean wall time of the runs so far times the runs left). On a terminal a line ticks in place
# while a run goes on; piped, only the finished lines are printed, plain.
coopnav_progress_start() {  # TOTAL
  _cn_prog_total=$1 _cn_prog_done=0 _cn_prog_wall_s=0 _cn_prog_ticker=""
}
coopnav_progress_eta() {  # the ETA of the runs not finished, from the mean of the finished ones
  local left=$((_cn_prog_total - _cn_prog_done))
  if [ "$_cn_prog_done" -eq 0 ]; then echo "ETA unknown"; return; fi
  awk -v w="$_cn_prog_wall_s" -v d="$_cn_prog_done" -v l="$left" \
    'BEGIN { e = w / d * l; if (l == 0) print "done"; else printf "ETA %.0f s", e }'
}
coopnav_progress_run() {  # LABEL: a run begins
  _cn_prog_label=$1
  _cn_prog_t0=$(date +%s.%N)
  [ -t 1 ] || return 0
  local n=$((_cn_prog_done + 1)) eta
  eta="$(coopnav_progress_eta)"
  (
    while sleep 1; do
      printf '\r\033[K[%d/%d] %s: running, %.0f s wall; %s' "$n" "$_cn_prog_total" \
        "$_cn_prog_label" "$(awk -v a="$_cn_prog_t0" -v b="$(date +%s.%N)" 'BEGIN{print b-a}')" \
        "$eta"
    done
  ) &
  _cn_prog_ticker=$!
}
coopnav_progress_end() {  # TRANSCRIPT: the run is over; its last SIM line gives time and outcome
  if [ -n "$_cn_prog_ticker" ]; then
    kill "$_cn_prog_ticker" 2>/dev/null || true
    wait "$_cn_prog_ticker" 2>/dev/null || true
    _cn_prog_ticker=""
    printf '\r\033[K'
  fi
  local wall sim outcome
  wall="$(awk -v a="$_cn_prog_t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}')"
  _cn_prog_done=$((_cn_prog_done + 1))
  _cn_prog_wall_s="$(awk -v a="$_cn_prog_wall_s" -v b="$wall" 'BEGIN{print a+b}')"
  sim="$(grep -o '^t=[0-9.]*s  SIM [A-Z_]*' "$1" 2>/dev/null | tail -1 || true)"
  outcome="${sim##* }"
  sim="${sim%%s  SIM*}"
  sim="${sim#t=}"
  printf '[%d/%d] %s: %s s simulated (%s) in %s s wall; %s\n' "$_cn_prog_done" "$_cn_prog_total" \
    "$_cn_prog_label" "${sim:-?}" "${outcome:-no end}" "$wall" "$(coopnav_progress_eta)"
}
