#!/usr/bin/env bash
# Architecture rules (ctest arch_rules, label unit). Fails, printing file:line and the rule, when
#  - a file under lib/ includes LCM (lcm/...), an lcmtype (coopnav/<type>_t.hpp or
#    coopnav/channels.hpp), or spdlog, or reads a clock (system_clock, steady_clock,
#    high_resolution_clock, time(nullptr), gettimeofday, clock_gettime; full comment lines are
#    skipped): lib/ is pure, the daemons do I/O, logging and time and hand lib/ plain values;
#  - a file under daemons/common includes a header of one daemon (daemons/<name>/, by path or by
#    a file name only that daemon has): common code is shared by all daemons and knows none;
#  - a shell script (scripts/, test/, tools/) sets a trap with `trap` rather than coopnav_trap
#    (scripts/lib.sh): bash can run a plain trap in a subshell that a signal reaches just after
#    fork, which ran a test's cleanup under its running daemons (RETURN traps and resets with
#    `trap -` are not affected; a line ending "# arch-rules: plain trap" is a deliberate one);
#  - a shell script (scripts/, test/, tools/) embeds Python (`python3 -c CODE`, `python3 -` or a
#    heredoc fed to python): code in strings is neither linted nor tested; it belongs in a module
#    (the experiment layer, tools/exp) or a script file of its own.
# Usage: test/arch_rules.sh [SOURCE_DIR]   (default: the repository holding this script)
#        test/arch_rules.sh --self-test    plants one violation of each rule in a scratch tree and
#                                          checks that every one is reported (ctest arch_rules_self_test)
set -uo pipefail

# check_tree ROOT: prints each violation, returns 1 if any.
check_tree() {
  local root=$1 violations=0 hits
  local src_glob=(--include='*.h' --include='*.hh' --include='*.hpp' --include='*.hxx'
                  --include='*.c' --include='*.cc' --include='*.cpp' --include='*.cxx'
                  --include='*.ipp' --include='*.inl' --include='*.tpp')
  local inc='^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]'
  # rule name | extended regex
  local rules=(
    "lib/ includes LCM|${inc}lcm/"
    "lib/ includes an lcmtype|${inc}coopnav/([A-Za-z0-9_]+_t|channels)\.hpp[>\"]"
    "lib/ includes spdlog|${inc}spdlog/"
    "lib/ reads a clock|(system_clock|steady_clock|high_resolution_clock|gettimeofday|clock_gettime|(^|[^A-Za-z0-9_.>])time[[:space:]]*\([[:space:]]*(nullptr|NULL|0)[[:space:]]*\))"
  )
  if [ -d "$root/lib" ]; then
    local rule name re
    for rule in "${rules[@]}"; do
      name=${rule%%|*}
      re=${rule#*|}
      # -H -n: file:line:text. Full comment lines (//, /*, *) do not count.
      hits=$(cd "$root" && grep -rHnE "${src_glob[@]}" -e "$re" lib |
             grep -vE '^[^:]+:[0-9]+:[[:space:]]*(//|/\*|\*)')
      if [ -n "$hits" ]; then
        violations=1
        while IFS= read -r h; do echo "ARCH RULE VIOLATED ($name): $h"; done <<<"$hits"
      fi
    done
  fi
  if [ -d "$root/daemons/common" ]; then
    local d name common_headers own_headers h hre
    common_headers=$(cd "$root/daemons/common" && find . -type f \( -name '*.h' -o -name '*.hpp' \) \
                       -printf '%f\n' | sort -u)
    for d in "$root"/daemons/*/; do
      name=$(basename "$d")
      [ "$name" = common ] && continue
      # By path: "band_source/x.hpp", "../band_source/x.hpp", "daemons/band_source/x.hpp".
      hre="${inc}((\.\./)+|daemons/)?${name}/"
      # By a file name only this daemon has: "band_source_node.hpp".
      own_headers=$(cd "$d" && find . -type f \( -name '*.h' -o -name '*.hpp' \) -printf '%f\n' |
                    sort -u | comm -23 - <(printf '%s\n' "$common_headers"))
      for h in $own_headers; do
        hre="$hre|${inc}${h//./\\.}[>\"]"
      done
      hits=$(cd "$root" && grep -rHnE "${src_glob[@]}" -e "$hre" daemons/common)
      if [ -n "$hits" ]; then
        violations=1
        while IFS= read -r h; do
          echo "ARCH RULE VIOLATED (daemons/common includes a header of daemon $name): $h"
        done <<<"$hits"
      fi
    done
  fi
  # Shell traps: a `trap` command word followed by a handler, outside comments.
  local dirs=() dd
  for dd in scripts test tools; do [ -d "$root/$dd" ] && dirs+=("$dd"); done
  if [ "${#dirs[@]}" -gt 0 ]; then
    hits=$(cd "$root" && grep -rHnE --include='*.sh' \
             -e '(^|[;&|({][[:space:]]*|(then|else|do)[[:space:]]+)trap[[:space:]]+[^-[:space:]]' \
             "${dirs[@]}" |
           grep -vE '^[^:]+:[0-9]+:[[:space:]]*#' | grep -vE '[[:space:]]RETURN;?[[:space:]]*}?[[:space:]]*$' |
           grep -vE '^scripts/lib\.sh:[0-9]+:.*_cn_trap_pid' | grep -vF '# arch-rules: plain trap')
    if [ -n "$hits" ]; then
      violations=1
      while IFS= read -r h; do
        echo "ARCH RULE VIOLATED (a shell trap without coopnav_trap): $h"
      done <<<"$hits"
    fi
    hits=$(cd "$root" && grep -rHnE --include='*.sh' \
             -e '(^|[^A-Za-z0-9_.-])python3?([[:space:]]+-c[[:space:]]|[[:space:]]+-([[:space:]]|$)|[[:space:]].*<<)' \
             "${dirs[@]}" | grep -vE '^[^:]+:[0-9]+:[[:space:]]*#')
    if [ -n "$hits" ]; then
      violations=1
      while IFS= read -r h; do
        echo "ARCH RULE VIOLATED (Python embedded in a shell script): $h"
      done <<<"$hits"
    fi
  fi
  return "$violations"
}

self_test() {
  local tmp out rc=0
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' RETURN
  mkdir -p "$tmp/lib/src/a" "$tmp/lib/include/coopnav/a" "$tmp/daemons/common/runtime" "$tmp/daemons/foo"
  # A clean tree passes (includes of lib headers, <chrono> durations, clocks named in comments).
  cat >"$tmp/lib/src/a/clean.cpp" <<'EOF'
#include "coopnav/a/clean.hpp"
#include "coopnav/geometry/types.hpp"
#include <chrono>
// The daemon reads steady_clock and passes the time in; lib never calls time(nullptr).
/* system_clock: not here either */
double f(double runtime) { return runtime * 2.0; }
EOF
  printf '#include "runtime/log.hpp"\n#include "coopnav/bands_t.hpp"\n' >"$tmp/daemons/common/c.cpp"
  : >"$tmp/daemons/common/runtime/log.hpp"
  : >"$tmp/daemons/foo/foo_node.hpp"
  : >"$tmp/daemons/foo/log.hpp"  # same name as a common header: not a daemon-only header
  mkdir -p "$tmp/scripts" "$tmp/test/e2e"
  cat >"$tmp/scripts/clean.sh" <<'EOF'
# trap 'x' EXIT in a comment, and the reset below, are fine
coopnav_trap 'rm -rf "$tmp"' EXIT
trap - INT TERM
f() { trap 'rm -rf "$d"' RETURN; }
# python3 -c "print(1)" in a comment is fine, as is running a Python file:
/usr/bin/python3 "$root/scripts/lint_units.py" "$db" | python3 tools/x.py -
EOF
  if ! out=$(check_tree "$tmp"); then
    echo "self-test: a clean tree was refused:"; echo "$out"; return 1
  fi
  # One violation of each kind.
  printf '#include <lcm/lcm-cpp.hpp>\n' >"$tmp/lib/src/a/v_lcm.cpp"
  printf '  #  include "coopnav/agent_states_t.hpp"\n' >"$tmp/lib/include/coopnav/a/v_type.hpp"
  printf '#include "coopnav/channels.hpp"\n' >"$tmp/lib/src/a/v_channels.cpp"
  printf '#include <spdlog/spdlog.h>\n' >"$tmp/lib/src/a/v_spdlog.cpp"
  printf 'auto t = std::chrono::steady_clock::now();\n' >"$tmp/lib/src/a/v_steady.cpp"
  printf 'auto t = std::chrono::system_clock::now();\n' >"$tmp/lib/src/a/v_system.cpp"
  printf 'auto t = std::chrono::high_resolution_clock::now();\n' >"$tmp/lib/src/a/v_hrc.cpp"
  printf 'long t = time(nullptr);\n' >"$tmp/lib/src/a/v_time.cpp"
  printf 'timeval tv; gettimeofday(&tv, nullptr);\n' >"$tmp/lib/src/a/v_gtod.cpp"
  printf 'timespec ts; clock_gettime(CLOCK_MONOTONIC, &ts);\n' >"$tmp/lib/src/a/v_cgt.cpp"
  printf '#include "foo/foo_node.hpp"\n' >"$tmp/daemons/common/v_path.cpp"
  printf '#include "../foo/foo_node.hpp"\n' >"$tmp/daemons/common/v_rel.hpp"
  printf '#include "foo_node.hpp"\n' >"$tmp/daemons/common/v_name.cpp"
  printf "trap 'rm -rf \"\$tmp\"' EXIT\n" >"$tmp/scripts/v_trap.sh"
  printf 'x=1; %s cleanup INT TERM\n' trap >"$tmp/test/e2e/v_trap_inline.sh"
  printf 'n=$(%s -c "print(2 * 3)")\n' python3 >"$tmp/scripts/v_py_c.sh"
  printf '%s - "$1" <<%s\n' /usr/bin/python3 "'PY'" >"$tmp/test/e2e/v_py_heredoc.sh"
  printf '  %s - "$port" >"$out" 2>&1 <<EOF &\n' python >"$tmp/test/e2e/v_py_redirect.sh"
  out=$(check_tree "$tmp") && { echo "self-test: violations were not reported"; return 1; }
  echo "$out"
  local f
  for f in v_lcm.cpp v_type.hpp v_channels.cpp v_spdlog.cpp v_steady.cpp v_system.cpp v_hrc.cpp \
           v_time.cpp v_gtod.cpp v_cgt.cpp v_path.cpp v_rel.hpp v_name.cpp v_trap.sh \
           v_trap_inline.sh v_py_c.sh v_py_heredoc.sh v_py_redirect.sh; do
    if ! grep -q "/$f:1:" <<<"$out"; then
      echo "self-test: the violation in $f was not reported"; rc=1
    fi
  done
  if grep -qE '(clean\.cpp|/c\.cpp|clean\.sh):' <<<"$out"; then
    echo "self-test: a clean file was reported"; rc=1
  fi
  [ "$rc" = 0 ] && echo "self-test: every rule fires, clean files pass"
  return "$rc"
}

if [ "${1:-}" = --self-test ]; then
  self_test
  exit $?
fi
root=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}
if check_tree "$root"; then
  echo "arch rules: lib/ has no LCM, lcmtype, spdlog or clock; daemons/common includes no daemon's" \
    "header; shell traps go through coopnav_trap; no shell script embeds Python"
else
  echo "arch rules violated (test/arch_rules.sh: lib/ is pure; daemons/common knows no daemon;" \
    "shell traps go through coopnav_trap; Python lives in .py files)"
  exit 1
fi
