"""`scripts/coopnav <command> ...`: one subcommand per module, registered here by one line each.

Each command's module exposes `add_arguments(parser: argparse.ArgumentParser)` and
`main(args: argparse.Namespace) -> int` (the process's exit status); its docstring's first line
is the command's help. A module's second command is a function with its own docstring and an
`add_arguments` attribute.
"""

from __future__ import annotations

import argparse
import inspect
import sys
from typing import Callable, Sequence

from . import ablation, faults, figures, metrics, multihost, population, run, system

COMMANDS: dict[str, Callable[[argparse.Namespace], int]] = {
    "ablation": ablation.main,
    "faults": faults.main,
    "figures": figures.main,
    "metrics": metrics.main,
    "multihost": multihost.main,
    "population": population.main,
    "run": run.main,
    "run-one": run.run_one_main,
    "outcome": run.outcome_main,
    "system": system.main,
}


class Parser(argparse.ArgumentParser):
    """Says "--out needs a value" for an option given last without its value (the scripts'
    wording, which their tests and users know)."""

    def error(self, message: str) -> None:  # type: ignore[override]
        if message.startswith("argument ") and message.endswith(": expected one argument"):
            opt = message[len("argument "):-len(": expected one argument")].split("/")[-1]
            message = f"{opt} needs a value (--help)"
        self.exit(2, f"{self.prog}: {message}\n")


def main(argv: Sequence[str] | None = None) -> int:
    parser = Parser(
        prog="coopnav", description="coopnav's experiment layer: runs, faults, populations.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, command in COMMANDS.items():
        # A module of one command: its add_arguments and docstring; a second command of a
        # module carries its own (a function attribute add_arguments, its docstring).
        module = sys.modules[command.__module__]
        add = getattr(command, "add_arguments", None)
        doc = inspect.cleandoc((command.__doc__ if add else module.__doc__) or "")
        help_line = doc.splitlines()[0] if doc else name
        p = sub.add_parser(name, help=help_line, description=doc,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        (add or module.add_arguments)(p)
        p.set_defaults(_command=command)
    args = parser.parse_args(argv)
    return int(args._command(args) or 0)
