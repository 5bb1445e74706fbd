#!/usr/bin/env bash
# The shortened soak of CI: scripts/soak.sh for one minute at 10x the nominal rates (the full
# 10-minute run and its figures: docs/soak.md). Fails on RSS growth > 5 % after warm-up, a growing
# backlog or lag, or a daemon that dies.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
source "$src/scripts/lib.sh"  # coopnav_trap
out="$(mktemp -d)"
coopnav_trap 'rm -rf "$out"' EXIT
rc=0
bash "$src/scripts/soak.sh" --minutes 1 --rate-factor 10 --no-build --out "$out" || rc=$?
if [ "$rc" -ne 0 ]; then
  for f in "$out"/*.log; do echo "== $f"; tail -20 "$f"; done
fi
exit "$rc"
