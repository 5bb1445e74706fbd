#!/usr/bin/env bash
# The scripts' bad arguments fail at once with a message that names them (no run started): an
# option given without its value, population.sh's unknown --profile and its -j beyond the cap;
# launch.sh reports a daemon that dies at start at once, with its exit status and its log's end,
# instead of waiting for ready until its timeout, and so does run.sh for a scenario whose map the
# daemons refuse. A few seconds.
set -euo pipefail
build="${COOPNAV_BUILD_DIR:?}"
src="${COOPNAV_SOURCE_DIR:?}"
export COOPNAV_BUILD_DIR="$build"
source "$src/scripts/lib.sh"  # coopnav_trap
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT
fail=0

# expect_usage WHAT GREP_PATTERN CMD...: CMD exits 2 within 10 s, saying GREP_PATTERN on stderr.
expect_usage() {
  local what="$1" pattern="$2" rc=0 err
  shift 2
  err="$(timeout 10 "$@" 2>&1 >/dev/null)" || rc=$?
  if [ "$rc" -ne 2 ] || ! grep -q -- "$pattern" <<<"$err"; then
    echo "FAIL $what: exit $rc, stderr: $err"
    fail=1
  elif grep -q "unbound variable" <<<"$err"; then
    echo "FAIL $what: bash's own error: $err"
    fail=1
  else
    echo "ok   $what"
  fi
}

for opt in --n --seed -j --out --profile; do  # population.sh: coopnav population's argparse
  expect_usage "population.sh $opt without a value" "$opt needs a value" \
    bash "$src/scripts/population.sh" --no-build "$opt"
done
for opt in --out --profile; do
  expect_usage "run.sh $opt without a value" "$opt needs a value" \
    bash "$src/scripts/run.sh" --no-build "$opt"
done
for opt in --out --seed --loss --kill --scenarios; do
  expect_usage "faults.sh $opt without a value" "$opt needs a value" \
    bash "$src/scripts/faults.sh" --no-build "$opt"
done
for opt in --url --map --log-dir; do
  expect_usage "launch.sh $opt without a value" "$opt needs a value" \
    bash "$src/scripts/launch.sh" "$opt"
done
expect_usage "population.sh --profile bogus" "profile must be paper, calibrated, forecast or make_time, not 'bogus'" \
  bash "$src/scripts/population.sh" --no-build --profile bogus --out "$tmp/pop"
expect_usage "population.sh --n x" "--n needs a count" \
  bash "$src/scripts/population.sh" --no-build --n x --out "$tmp/pop"
# The cap is said, then the bad profile stops the script before any run.
expect_usage "population.sh -j 3000000" "-j 3000000 capped to $((4 * $(nproc)))" \
  bash "$src/scripts/population.sh" --no-build -j 3000000 --profile bogus --out "$tmp/pop"
[ ! -e "$tmp/pop" ] || { echo "FAIL population.sh made its output before checking"; fail=1; }

# launch.sh: the path assessor stops at start on a bad setting (exit 2); launch.sh says so at
# once, with the status and the daemon's own message, well before wait-ready's 30 s.
start=$(date +%s)
rc=0
err="$(COOPNAV_DAEMON_ARGS_path_assessor="--set no_such_key_xyz=1" timeout 25 \
  bash "$src/scripts/launch.sh" --log-dir "$tmp/launch" path_assessor 2>&1 >/dev/null)" || rc=$?
took=$(($(date +%s) - start))
if [ "$rc" -ne 1 ] || [ "$took" -gt 10 ] ||
  ! grep -q "path_assessor exited at start (status 2)" <<<"$err" ||
  ! grep -q "path_assessor: .*no_such_key_xyz" <<<"$err"; then
  echo "FAIL launch.sh with a daemon dying at start: exit $rc after $took s: $err"
  fail=1
else
  echo "ok   launch.sh reports a daemon dying at start after $took s"
fi

# run.sh with a scenario whose map the daemons refuse: the reason at once, not 60 s of waiting.
sed 's/^name: .*/name: bad_map/; s/^  resolution_m: .*/  resolution_m: 50/' \
  "$src/config/scenarios/open_minimal.yaml" >"$tmp/bad_map.yaml"
grep -q "resolution_m: 50" "$tmp/bad_map.yaml" || { echo "FAIL: no resolution_m to bend"; fail=1; }
start=$(date +%s)
rc=0
err="$(COOPNAV_RUN_PORT_BASE="${COOPNAV_TEST_PORT_BASE:-7670}" timeout 50 \
  bash "$src/scripts/run.sh" --no-build --out "$tmp/run" "$tmp/bad_map.yaml" 2>&1 >/dev/null)" ||
  rc=$?
took=$(($(date +%s) - start))
if [ "$rc" -eq 0 ] || [ "$rc" -eq 124 ] || [ "$took" -gt 20 ] ||
  ! grep -q "exited at start (status 3)" <<<"$err" || ! grep -q "resolution" <<<"$err"; then
  echo "FAIL run.sh with a bad map: exit $rc after $took s: $err"
  fail=1
else
  echo "ok   run.sh says why a scenario's map is refused after $took s"
fi

[ "$fail" -eq 0 ] && echo "PASS" || { echo "FAIL"; exit 1; }
