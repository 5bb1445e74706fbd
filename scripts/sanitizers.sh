# Sourced by scripts/test.sh (after lib.sh): the test suite again under sanitizers, in build
# directories of their own. Why these labels and options: docs/sanitizers.md.

# coopnav_sanitizer_pass NAME SANITIZE TARGETS CTEST_ARGS...
#   configures build-NAME with -DCOOPNAV_SANITIZE=SANITIZE (benchmarks off), builds only TARGETS
#   (space-separated: what the selected tests run; a sanitized build of everything costs minutes
#   of a 2-core machine for nothing), runs ctest with CTEST_ARGS and then e2e_lifecycle_test, and
#   fails on a failed test or on any sanitizer report. Reports go to files (log_path) because most
#   of them come from daemons started by the tests as child processes, whose stderr a passing
#   test would hide.
coopnav_sanitizer_pass() {
  local name="$1" sanitize="$2" targets="$3"
  shift 3
  local dir="$COOPNAV_ROOT/build-$name"
  local logs="$dir/sanitizer-reports"
  local t0=$SECONDS
  # -O1 -g1: sanitizer stacks need line tables only, and most of a sanitized build's time is -O2
  # optimisation and full debug info of instrumented template code (docs/sanitizers.md).
  COOPNAV_BUILD_DIR="$dir" COOPNAV_BUILD_TARGETS="$targets" coopnav_build \
    -DCOOPNAV_SANITIZE="$sanitize" -DCOOPNAV_BUILD_BENCH=OFF \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"
  echo "coopnav: $name: built in $((SECONDS - t0)) s"
  rm -rf "$logs"
  mkdir -p "$logs"
  local common="halt_on_error=1:abort_on_error=1:print_stacktrace=1:log_path=$logs/report"
  local supp="$COOPNAV_ROOT/test/sanitizers"
  export ASAN_OPTIONS="$common:detect_leaks=1:detect_stack_use_after_return=1"
  export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="$common"
  export TSAN_OPTIONS="$common:second_deadlock_stack=1:suppressions=$supp/tsan.supp"
  # TSan maps its shadow memory at fixed addresses; a kernel with more ASLR entropy than it
  # expects (vm.mmap_rnd_bits > 28) makes it fail at start ("unexpected memory mapping"). Run
  # without ASLR where the personality may be changed (not in every container).
  local run=()
  if [ "$name" = tsan ] && setarch "$(uname -m)" -R true 2>/dev/null; then
    run=(setarch "$(uname -m)" -R)
  fi
  local rc=0
  (cd "$dir" && "${run[@]}" ctest --output-on-failure --timeout 1800 -j"$(nproc)" "$@") || rc=1
  (cd "$dir" && "${run[@]}" ctest --output-on-failure --timeout 1800 -R '^e2e_lifecycle_test$') ||
    rc=1
  if compgen -G "$logs/report*" >/dev/null; then
    echo "coopnav: $name: sanitizer reports:" >&2
    cat "$logs"/report* >&2
    rc=1
  fi
  unset ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS TSAN_OPTIONS
  echo "coopnav: $name: pass took $((SECONDS - t0)) s (build and tests)"
  [ "$rc" -eq 0 ] && echo "coopnav: $name: clean"
  return "$rc"
}
