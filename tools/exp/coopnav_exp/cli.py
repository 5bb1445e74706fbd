"""`scripts/coopnav <command> ...`: one subcommand per module, registered here by one line each.

Each command's module exposes `add_arguments(parser: argparse.ArgumentParser)` and
`main(args: argparse.Namespace) -> int` (the process's exit status); its docstring's first line
is the command's help.
"""

from __future__ import annotations

import argparse
import sys
from typing import Callable, Sequence

COMMANDS: dict[str, Callable[[argparse.Namespace], int]] = {
}


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="coopnav", description="coopnav's experiment layer: runs, faults, populations.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, command in COMMANDS.items():
        module = sys.modules[command.__module__]
        doc = (module.__doc__ or "").strip()
        help_line = doc.splitlines()[0] if doc else name
        p = sub.add_parser(name, help=help_line, description=doc,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        module.add_arguments(p)
        p.set_defaults(_command=command)
    args = parser.parse_args(argv)
    return int(args._command(args) or 0)
