#!/usr/bin/env bash
# The daemons across hosts (README "Network and hosts"; the full run is scripts/multihost.sh):
# every process on a network namespace of its own, joined by veth pairs on a bridge, multicast
# with ttl=1. The four paper scenarios must give transcripts byte-identical to a single-host run;
# with every link lossy (5 %; netem with 20 ms +- 5 ms delay where the kernel has it, else a lossy
# relay on every host) the decisions must stay the clean ones; when the path assessor's host
# drops off mid-run, the world must stop the run naming it and nothing decided may differ.
# Selection (~2 min on the shared 2-core machine): the single-host comparison on all four
# scenarios, the loss pass on two of them (narrow_minimal: a dock and every round; open_minimal:
# a spoken side at round 2) since all four take ~2 more minutes, the drop-off on narrow_minimal
# (~25 s, most of it the scenario's 20 s step timeout).
# Needs root for network namespaces: skipped (exit 77) where they cannot be made.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
tmp="$(mktemp -d)"
coopnav_trap 'rm -rf "$tmp"' EXIT
# Ports of this test only (its block from COOPNAV_TEST_PORT_BASE, test/CMakeLists.txt): base to
# base + 4 on this machine; the namespaced hosts' ports are their own.
rc=0
COOPNAV_MULTIHOST_PORT_BASE=$COOPNAV_TEST_PORT_BASE bash "$src/scripts/multihost.sh" --no-build --out "$tmp/a" \
  --loss-scenarios "narrow_minimal open_minimal" --dropoff-scenario narrow_minimal \
  >"$tmp/out.txt" 2>&1 || rc=$?
cat "$tmp/out.txt"
if [ "$rc" -eq 77 ]; then exit 77; fi
if [ "$rc" -ne 0 ]; then
  for f in "$tmp"/a/*/*/world_sim.log "$tmp"/a/*/*/*/world_sim.log; do
    if [ -f "$f" ]; then echo "--- $f"; tail -3 "$f"; fi
  done
  echo "FAIL: multihost runs"
  exit 1
fi
# No host or switch may outlive the script (its trap removes them; the prefix is in its output).
prefix="$(grep -m1 -o 'namespaces cnmh[0-9]*' "$tmp/out.txt" | sed 's/namespaces //' || true)"
if [ -z "$prefix" ]; then
  echo "FAIL: no namespace prefix in the output"
  exit 1
fi
if ip netns list | grep "^$prefix-" >/dev/null; then
  echo "FAIL: namespaces left behind:"; ip netns list
  exit 1
fi
echo "multihost: all checks pass"
