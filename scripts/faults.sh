#!/usr/bin/env bash
# Fault runs of the paper's scenarios (README "Faults"): each scenario clean, with each daemon
# killed (-9) at a seeded random step and started again with its journal, without the distance
# server, and under 10 % message loss; a verdict per run (same / degraded / FAIL) against the
# clean run's decisions.
#
#   scripts/faults.sh [--out DIR] [--no-build] [--seed N] [--loss P]
#                     [--scenarios "open_minimal ..."] [--kill "band_source ..."]
#                     [--kills-per-scenario N] [--no-absent] [--no-loss] [--no-kill]
#                     [--loss-seed N] [--absent-in "narrow_minimal ..."]
#
# The program is `scripts/coopnav faults` (tools/exp/coopnav_exp/faults.py; --help says
# everything).
exec "$(dirname "${BASH_SOURCE[0]}")/coopnav" faults "$@"
