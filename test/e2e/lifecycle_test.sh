#!/usr/bin/env bash
# Every daemon, as a real process: --help exits 0, a bad setting exits 2 naming the key, a
# status message appears, and SIGTERM / SIGINT stop it with exit 0 within 1 s.
set -euo pipefail
build="${COOPNAV_BUILD_DIR:?}"
src="${COOPNAV_SOURCE_DIR:?}"
ctl="$build/tools/coopnav_ctl"
scenario="$src/config/scenarios/open_minimal.yaml"
fail=0

args_for() {
  case "$1" in
    obstacle_distance_server|band_source) echo "-c $src/config/$1.yaml --set map_file=$scenario" ;;
    world_sim) echo "-c $src/config/world_sim.yaml --set scenario=$scenario" ;;
    viewer) echo "-c $src/config/viewer.yaml --set http_port=0" ;;
    *) echo "-c $src/config/$1.yaml" ;;
  esac
}

# Every daemon of the source tree (a folder of daemons/ with a CMakeLists.txt, but common/).
daemons=()
for dir in "$src"/daemons/*/; do
  d="$(basename "$dir")"
  [ "$d" != common ] && [ -f "$dir/CMakeLists.txt" ] && daemons+=("$d")
done
[ "${#daemons[@]}" -gt 0 ] || { echo "FAIL: no daemons found under $src/daemons"; exit 1; }
for d in "${daemons[@]}"; do
  exe="$build/daemons/$d/coopnav_$d"
  [ -x "$exe" ] || { echo "FAIL $d: $exe not built"; fail=1; continue; }
  "$exe" --help >/dev/null || { echo "FAIL $d: --help"; fail=1; }
  rc=0
  err="$("$exe" $(args_for "$d") --set no_such_key_xyz=1 2>&1 >/dev/null)" || rc=$?
  if [ "$rc" -ne 2 ] || ! grep -q no_such_key_xyz <<<"$err"; then
    echo "FAIL $d: unknown config key gave exit $rc: $err"; fail=1
  fi
  for sig in TERM INT; do
    # shellcheck disable=SC2046
    "$exe" $(args_for "$d") --log-level warn &
    pid=$!
    if ! "$ctl" wait-ready "$d" --timeout-s 30 >/dev/null; then
      echo "FAIL $d: no status message"; fail=1
    fi
    kill -"$sig" "$pid"
    t0=$(date +%s%N)
    rc=0
    wait "$pid" || rc=$?
    ms=$(( ($(date +%s%N) - t0) / 1000000 ))
    if [ "$rc" -ne 0 ] || [ "$ms" -gt 1000 ]; then
      echo "FAIL $d: SIG$sig -> exit $rc after $ms ms"; fail=1
    else
      echo "ok   $d: SIG$sig -> exit 0 after $ms ms"
    fi
  done
done
exit "$fail"
