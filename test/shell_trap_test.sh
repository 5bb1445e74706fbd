#!/usr/bin/env bash
# coopnav_trap (scripts/lib.sh), ctest shell_trap_test: a script's traps run in that script only.
# Subshells stopped with SIGTERM right after their fork (as a watchdog or a ticker is) must not
# run their parent's EXIT trap; the parent must run it once at its exit, and its TERM trap when
# it is signalled. Plain `trap` in the same loop is run for comparison and printed, not judged
# (how often it leaks depends on bash's version and the machine's load).
set -euo pipefail
lib="$(cd "$(dirname "${BASH_SOURCE[0]}")/../scripts" && pwd)/lib.sh"
tmp="$(mktemp -d)"
rm_tmp() { rm -rf "$tmp"; }
source "$lib"
coopnav_trap rm_tmp EXIT
N=300

# loop MODE DIR: N subshells, each killed with SIGTERM at once; every shell that runs the EXIT
# trap leaves a file named by its pid in DIR. Prints the loop's own pid.
loop() {
  mkdir -p "$2"
  # shellcheck disable=SC2016 # expanded by the inner bash
  bash -c '
    source "$1"; set +e
    dir="$2"
    mark() { read -r me _ </proc/self/stat; : >"$dir/$me"; }
    if [ "$3" = guarded ]; then coopnav_trap "mark" EXIT; else trap "mark" EXIT; fi # arch-rules: plain trap
    for _ in $(seq 1 "$4"); do (sleep 5 && true) >/dev/null & w=$!; kill "$w"; wait "$w"; done
    read -r me _ </proc/self/stat; echo "$me"' loop "$lib" "$2" "$1" "$N" 2>/dev/null
}

fail=0
main_pid=$(loop guarded "$tmp/guarded")
others=$(find "$tmp/guarded" -type f ! -name "$main_pid" | wc -l)
if [ ! -e "$tmp/guarded/$main_pid" ]; then echo "FAIL: the shell that set the trap did not run it"; fail=1; fi
if [ "$others" -ne 0 ]; then echo "FAIL: $others of $N subshells ran their parent's EXIT trap"; fail=1; fi
echo "coopnav_trap: run by the shell that set it, by $others of $N subshells killed at once"

plain_pid=$(loop plain "$tmp/plain")
leaks=$(find "$tmp/plain" -type f ! -name "$plain_pid" | wc -l)
echo "plain trap (for comparison, bash $BASH_VERSION): run by $leaks of $N subshells killed at once"

# A TERM trap set with coopnav_trap still stops the shell that set it.
# shellcheck disable=SC2016
bash -c 'source "$1"; coopnav_trap "kill \$!; echo stopped; exit 143" TERM; echo up; sleep 30 & wait' \
  term "$lib" >"$tmp/term.out" 2>&1 &
term_pid=$!
for _ in $(seq 100); do grep -q up "$tmp/term.out" && break; sleep 0.05; done
kill -TERM "$term_pid"
rc=0
wait "$term_pid" || rc=$?
if [ "$rc" -ne 143 ] || ! grep -q stopped "$tmp/term.out"; then
  echo "FAIL: a TERM trap set with coopnav_trap: exit $rc, output: $(cat "$tmp/term.out")"
  fail=1
fi
[ "$fail" -eq 0 ] && echo "shell traps: coopnav_trap runs in its own shell only"
exit "$fail"
