#!/usr/bin/env bash
# The daemons across hosts (README "Network and hosts"), network namespaces for hosts: every
# process of a run on a host of its own; the transcripts must be the single-host ones, with loss
# the decisions must stay the clean ones, a host that drops off must stop the run, and the
# recipe of scripts/launch.sh on three hosts must give the single-host transcript. Needs root;
# "SKIP: <reason>" and exit 77 where namespaces cannot be made.
#
#   scripts/multihost.sh [--out DIR] [--no-build] [--scenarios "open_minimal ..."]
#                        [--loss-scenarios "narrow_minimal ..."] [--no-loss] [--loss P]
#                        [--delay "20ms 5ms"] [--loss-seed N] [--dropoff-scenario NAME]
#                        [--no-dropoff] [--no-launch] [--port-base N]
#
# The program is `scripts/coopnav multihost` (tools/exp/coopnav_exp/multihost.py; --help says
# everything, the verdicts included).
exec "$(dirname "${BASH_SOURCE[0]}")/coopnav" multihost "$@"
