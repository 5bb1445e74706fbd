#!/usr/bin/python3
"""The translation units clang-tidy checks (scripts/lint.sh --tidy), one absolute path a line.

    scripts/lint_units.py COMPILE_COMMANDS ROOT MODE [FILE...]

FILEs given: exactly those (each must be in the compile commands, else exit 1 naming it).
Otherwise MODE tidy-all: every unit; any other MODE: the units whose path relative to ROOT fully
matches a pattern of LINT_SET (regular expressions, one a line, from the environment) and none of
LINT_EXCLUDE.
"""
import json
import os
import re
import sys


def main(argv: list[str]) -> int:
    db, root, mode, args = argv[0], argv[1], argv[2], argv[3:]
    include = [line for line in os.environ.get("LINT_SET", "").split("\n") if line]
    exclude = [line for line in os.environ.get("LINT_EXCLUDE", "").split("\n") if line]
    with open(db) as f:
        units = sorted({os.path.normpath(os.path.join(e["directory"], e["file"]))
                        for e in json.load(f)})

    def rel(u: str) -> str:
        return os.path.relpath(u, root)

    if args:
        want = {os.path.normpath(os.path.abspath(a)) for a in args}
        missing = sorted(want - set(units))
        for m in missing:
            print("lint: not in the compile commands: " + m, file=sys.stderr)
        if missing:
            return 1
        units = [u for u in units if u in want]
    elif mode != "tidy-all":
        units = [u for u in units
                 if any(re.fullmatch(p, rel(u)) for p in include)
                 and not any(re.fullmatch(p, rel(u)) for p in exclude)]
    print("\n".join(units))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
