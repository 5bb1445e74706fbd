#!/usr/bin/env bash
# Lint (CI: scripts/test.sh after the tests; COOPNAV_LINT=0 skips it there):
#   1. clang-format --dry-run --Werror (.clang-format) on every tracked *.cpp / *.hpp;
#   2. clang-tidy (.clang-tidy, every enabled check an error) on the translation units of
#      TIDY_SET below, with the compile commands of the build ($COOPNAV_BUILD_DIR, configured if
#      missing; the generated lcmtypes headers are made first), -j$(nproc) in parallel.
# Any finding fails the run; each is printed as file:line:col: message [check].
#
#   scripts/lint.sh                 both steps, the CI set
#   scripts/lint.sh --format        only the clang-format check
#   scripts/lint.sh --tidy [FILE..] only clang-tidy: the CI set, or these files (each must be in
#                                   the compile commands: lib/daemons/tools/test/bench sources)
#   scripts/lint.sh --tidy-all      clang-tidy on every translation unit of the build (tests and
#                                   benchmarks too; ~10 min on 2 cores)
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

# The clang-tidy set: what CI checks, chosen to keep this step within ~3 min on 2 cores.
# Measured here (clang-tidy 14 with this .clang-tidy; CPU seconds per translation unit, user + sys,
# on 2 cores with a load of ~5, so about 1.4x what an idle machine takes):
#   all 61 units of daemons/, tools/, lib/                       514 s
#   this set: 49 units                                           367 s  (~3 min at -j2)
#     daemons/ nodes and common/ 3-18 s each (world_sim_node 18, dialogue_manager_node 15),
#     tools/ 3-15 s, lib/ 1-8 s; most of it is parsing and matching the headers (Eigen, LCM,
#     spdlog / fmt, CLI11, yaml-cpp, nlohmann-json)
#   left out (147 s):
#     daemons/*/main.cpp, 6 units of 12-15 s each: five lines around runDaemon<Node>, all of the
#       time in headers; daemon_main.hpp is checked through daemons/common/runtime/daemon_main.cpp
#     daemons/band_source/band_source_node.cpp (18 s) and the band's Ceres-template / solver units
#       lib/src/band/{band_optimizer,sparse_lm,dual_band_planner,block_ldlt,
#       holonomic_motion_costs}.cpp (6-16 s each): the heaviest per line of our code
#   Headers of lib/include/coopnav/band are still checked through the units of the set that
#   include them (band_config, velocity_command, timed_elastic_band, sim/*).
# Tests and benchmarks are left out too (51 units, ~10 s each). `--tidy-all` checks everything.
TIDY_SET=(
  'daemons/.*\.cpp'
  'tools/.*\.cpp'
  'lib/src/(geometry|distance|planning|assessment|dialogue|sim|metrics)/.*\.cpp'
  'lib/src/band/(band_config|velocity_command|timed_elastic_band)\.cpp'
)
TIDY_EXCLUDE=(
  'daemons/band_source/.*'
  'daemons/[^/]+/main\.cpp'
)
# Not ours to format: generated code (lcm-gen writes into the build tree, which is untracked;
# anything tracked under a gen/ directory would be generated too).
FORMAT_EXCLUDE='(^|/)gen/'

mode=all
files=()
case "${1:-}" in
  --format) mode=format ;;
  --tidy)
    mode=tidy
    shift
    files=("$@")
    ;;
  --tidy-all) mode=tidy-all ;;
  "") ;;
  *)
    echo "usage: scripts/lint.sh [--format | --tidy [FILE...] | --tidy-all]" >&2
    exit 2
    ;;
esac

coopnav_lint_tool() {  # coopnav_lint_tool NAME: NAME-14 if present, else NAME
  if command -v "$1-14" >/dev/null; then echo "$1-14"; elif command -v "$1" >/dev/null; then
    echo "$1"
  else
    echo "lint: $1 missing (Debian: clang-format clang-tidy)" >&2
    return 1
  fi
}

rc=0
cd "$COOPNAV_ROOT" || exit 1

# --- 1. clang-format -------------------------------------------------------------------------
lint_format() {
  local cf t0=$SECONDS
  cf=$(coopnav_lint_tool clang-format) || return 1
  local list=()
  if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    mapfile -t list < <(git ls-files -- '*.cpp' '*.hpp' | grep -Ev "$FORMAT_EXCLUDE" || true)
  else
    mapfile -t list < <(find lib daemons tools test bench lcmtypes -name '*.[ch]pp' |
      grep -Ev "$FORMAT_EXCLUDE" | sort)
  fi
  # Tracked but deleted in the working tree: nothing to check.
  local present=() f
  for f in "${list[@]}"; do [ -f "$f" ] && present+=("$f"); done
  if [ "${#present[@]}" -eq 0 ]; then
    echo "lint: clang-format: no C++ file found" >&2
    return 1
  fi
  local out bad
  out=$("$cf" --dry-run --Werror "${present[@]}" 2>&1) || true
  bad=$(grep -oE '^[^:]+\.(cpp|hpp):[0-9]+:[0-9]+: error' <<<"$out" | cut -d: -f1 | sort -u || true)
  if [ -n "$bad" ]; then
    echo "lint: clang-format: $(wc -l <<<"$bad") of ${#present[@]} files are not formatted" \
      "(.clang-format; fix: $cf -i FILE...):"
    sed 's/^/  /' <<<"$bad"
    echo "  first differences:"
    grep -E '^[^:]+\.(cpp|hpp):[0-9]+:[0-9]+: error' <<<"$out" | head -20 | sed 's/^/    /'
    return 1
  fi
  if [ -n "$out" ]; then  # an error that is not a formatting difference (unreadable file, ...)
    echo "$out" >&2
    return 1
  fi
  echo "lint: clang-format: ${#present[@]} files formatted ($((SECONDS - t0)) s)"
}

# --- 2. clang-tidy ---------------------------------------------------------------------------
lint_tidy() {
  local ct t0=$SECONDS
  ct=$(coopnav_lint_tool clang-tidy) || return 1
  local db="$COOPNAV_BUILD_DIR/compile_commands.json"
  if [ ! -f "$db" ]; then
    cmake -S "$COOPNAV_ROOT" -B "$COOPNAV_BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      >/dev/null
  fi
  # daemons / tools include the lcm-gen headers (build tree).
  cmake --build "$COOPNAV_BUILD_DIR" --target coopnav_lcmtypes_gen >/dev/null

  # The translation units: absolute paths of the compile commands that the set selects.
  local sel units=()
  sel=$(LINT_SET="$(printf '%s\n' "${TIDY_SET[@]}")" \
    LINT_EXCLUDE="$(printf '%s\n' "${TIDY_EXCLUDE[@]}")" \
    /usr/bin/python3 "$COOPNAV_ROOT/scripts/lint_units.py" "$db" "$COOPNAV_ROOT" "$mode" \
      "${files[@]}"
  ) || return 1
  [ -n "$sel" ] && mapfile -t units <<<"$sel"
  if [ "${#units[@]}" -eq 0 ]; then
    echo "lint: clang-tidy: no translation unit selected" >&2
    return 1
  fi
  local jobs
  jobs=$(nproc)
  local log
  log=$(mktemp)
  local trc=0
  local runner
  if runner=$(coopnav_lint_tool run-clang-tidy 2>/dev/null); then
    # run-clang-tidy takes regular expressions: one anchored per file.
    local res=() u
    for u in "${units[@]}"; do res+=("^$(sed 's/[][\.*^$+?(){}|]/\\&/g' <<<"$u")\$"); done
    "$runner" -clang-tidy-binary "$ct" -p "$COOPNAV_BUILD_DIR" -j "$jobs" -quiet "${res[@]}" \
      >"$log" 2>&1 || trc=1
  else
    printf '%s\0' "${units[@]}" |
      xargs -0 -n1 -P "$jobs" "$ct" -p "$COOPNAV_BUILD_DIR" --quiet >"$log" 2>&1 || trc=1
  fi
  # Findings (a header's finding comes once per unit including it: shown once).
  local findings
  sed -i 's/\x1b\[[0-9;]*m//g' "$log"  # run-clang-tidy-14 always asks for colours
  findings=$(grep -E '^[^ ].*:[0-9]+:[0-9]+: (error|warning): .*\[[a-z0-9.,-]+\]$' "$log" |
    sed "s|^$COOPNAV_ROOT/||" | sort -u || true)
  local dt=$((SECONDS - t0))
  if [ -n "$findings" ]; then
    echo "lint: clang-tidy: $(wc -l <<<"$findings") findings in ${#units[@]} translation units" \
      "($dt s):"
    sed 's/^/  /' <<<"$findings"
    echo "  (details: clang-tidy -p $COOPNAV_BUILD_DIR FILE; a false positive: // NOLINT(check))"
    rm -f "$log"
    return 1
  fi
  if [ "$trc" -ne 0 ]; then  # no finding, yet a failure: compile errors, a crash
    echo "lint: clang-tidy failed ($dt s):" >&2
    grep -v -E '^(Suppressed [0-9]+ warnings|Use -header-filter|[0-9]+ warnings? generated)' "$log" |
      grep -v -E "^$ct " | tail -40 >&2
    rm -f "$log"
    return 1
  fi
  rm -f "$log"
  echo "lint: clang-tidy: ${#units[@]} translation units in $dt s, no finding"
}

if [ "$mode" = all ] || [ "$mode" = format ]; then lint_format || rc=1; fi
if [ "$mode" != format ]; then lint_tidy || rc=1; fi
exit "$rc"
