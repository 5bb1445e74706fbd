#!/usr/bin/env bash
# The documents say what the scripts do: every option the README (and docs/*.md) quote for a
# script, as in `scripts/run.sh --no-build --profile calibrated`, is one that script's --help
# names (an option the script does not know would fail a new user at once).
# The scenario-format example is loaded by node_world_sim_scenario_files_test
# (ScenarioFiles.TheFormatDocumentsExampleLoads). A few seconds.
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:?}"
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"  # textspy.sh --help runs its Java class
fail=0
checked=0

# "script option" per line: each option quoted after scripts/<name>.sh, up to the end of the
# inline code span, a blank line, a shell comment or the next command.
quoted="$(python3 - "$src" "$src/README.md" "$src"/docs/*.md <<'EOF'
import re, sys
for path in sys.argv[2:]:
    text = open(path, encoding="utf-8").read()
    for m in re.finditer(r"scripts/([a-z_]+\.sh)", text):
        rest = text[m.end():]
        end = len(rest)
        for stop in ("`", "\n\n", " #", "scripts/", ";", " | ", "&&", "\n```"):
            i = rest.find(stop)
            if i >= 0:
                end = min(end, i)
        for opt in re.findall(r"(?:^|[\s\[])(--[a-z][a-z0-9-]*|-j)\b", rest[:end]):
            print(m.group(1), opt, path[len(sys.argv[1]) + 1:])
EOF
)"
[ -n "$quoted" ] || { echo "FAIL: no quoted script option found"; exit 1; }

declare -A help_of=()
while read -r script opt where; do
  if [ -z "${help_of[$script]+x}" ]; then
    help_of[$script]="$(timeout 10 bash "$src/scripts/$script" --help 2>&1)" ||
      { echo "FAIL scripts/$script --help does not exit 0 (quoted in $where)"; fail=1; }
  fi
  checked=$((checked + 1))
  if ! grep -q -- "$opt\b" <<<"${help_of[$script]}"; then
    echo "FAIL $where quotes scripts/$script $opt, which its --help does not name"
    fail=1
  fi
done <<<"$(sort -u <<<"$quoted")"
echo "checked $checked quoted options:"; sort -u <<<"$quoted" | sed "s/^/  /"

[ "$fail" -eq 0 ] && echo "PASS" || { echo "FAIL"; exit 1; }
