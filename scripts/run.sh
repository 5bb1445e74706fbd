#!/usr/bin/env bash
# The main job: runs the paper's experiment (§III). For each scenario it starts the daemons as
# separate processes on a host-local LCM port of its own, runs the world simulator in lockstep,
# records an LCM log, and prints the transcript (what the robot said and did, when, and why);
# then the CM table beside the paper's Table I. Writes runs/<timestamp>/ and runs/latest.
#
#   scripts/run.sh [--out DIR] [--no-build] [--profile paper|calibrated|forecast|make_time] [--speech]
#                  [scenario.yaml ...]
#
# The program is `scripts/coopnav run` (tools/exp/coopnav_exp/run.py; --help says everything).
exec "$(dirname "${BASH_SOURCE[0]}")/coopnav" run "$@"
