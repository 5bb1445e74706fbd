# Sourced by e2e_hostile_test and e2e_flood_test (docs/bad-inputs.md "Hostile publisher"): the
# resident memory [MiB] each daemon must stay under during any probe or flood, and the daemons
# themselves, read from config/system.yaml (`scripts/coopnav system daemons`).
# Idle with the shipped configs (RelWithDebInfo): distance server 27, band source 17, the others
# 7. The caps leave room for what the attacks may legitimately fill (LCM's receive queue, the
# capped per-id state, the ~100 B LCM keeps per channel name: 100 000 reply channels ~10 MiB at
# the distance server), and are far below what the unbounded versions reached (hundreds of MiB
# to GiB).
declare -A RSS_CAP_MIB=(
  [obstacle_distance_server]=64
  [band_source]=64
  [situation_assessor]=48
  [path_assessor]=48
  [dialogue_manager]=48
  [world_sim]=64
)
# DAEMONS: system.yaml's daemons in start order; DAEMON_BIN[name]: the executable of each and of
# the world. A daemon without a cap above stops the test: a new daemon gets its cap here.
mapfile -t DAEMONS < <("${COOPNAV_SOURCE_DIR:?}/scripts/coopnav" system daemons)
[ "${#DAEMONS[@]}" -gt 0 ] || { echo "FAIL: scripts/coopnav system daemons named none"; exit 1; }
declare -A DAEMON_BIN=()
for _d in "${DAEMONS[@]}" world_sim; do
  [ -n "${RSS_CAP_MIB[$_d]:-}" ] || { echo "FAIL: no RSS cap for daemon $_d (test/e2e/rss_caps.sh)"; exit 1; }
  DAEMON_BIN[$_d]="$("$COOPNAV_SOURCE_DIR/scripts/coopnav" system binary "$_d")"
done
unset _d
