#!/usr/bin/env bash
# A population of head-on corridor (or crowd) encounters (docs/population.md): generates N
# scenario files from a seed (tools/population), runs them JOBS at a time, each on a udpm port of
# its own and in a folder of its own, plus one run without humans per corridor layout (the
# time-to-goal baseline), and writes DIR/population.json and DIR/population.txt. Exit non-zero:
# 1 a contact with the robot at fault; 4 a failed dialogue check (words to someone not crossed, a
# contradiction, a group told twice, unaddressed among several); 5 a run ended in any contact, a
# standstill, the time limit or a mutual wait over 10 s (why on stderr); 3 a run left no summary;
# muted twins included; 2 bad arguments or files. A line per finished run says where it stands.
#
#   scripts/population.sh [--n N] [--seed S] [-j JOBS] [--out DIR] [--no-build]
#                         [--tracker-noise] [--goals-withheld] [--profile paper|calibrated|forecast|make_time]
#                         [--realistic-timing] [--cue-effect | --crowd] [--slurm ...]
#
# The entry point of `scripts/coopnav population` (tools/exp/coopnav_exp/population.py: the
# options, the job pool, Slurm); `scripts/population.sh --help` lists every option.

exec "$(dirname "${BASH_SOURCE[0]}")/coopnav" population "$@"
