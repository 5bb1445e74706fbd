"""Shared by the experiment layer's pytest files: the package on sys.path, the build and
source folders (COOPNAV_BUILD_DIR / COOPNAV_SOURCE_DIR from ctest, else the repository's), and
a port block of each e2e test's own (COOPNAV_TEST_PORT_BASE, test/py/CMakeLists.txt)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("COOPNAV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
sys.path.insert(0, str(SOURCE_DIR / "tools" / "exp"))


@pytest.fixture
def source_dir() -> Path:
    return SOURCE_DIR


@pytest.fixture
def build_dir() -> Path:
    return Path(os.environ.get("COOPNAV_BUILD_DIR") or SOURCE_DIR / "build")


@pytest.fixture
def port_base() -> int:
    return int(os.environ.get("COOPNAV_TEST_PORT_BASE", "40000"))


def run_sh(source: Path, out: Path, *scenarios: Path | str, port: int, args: tuple = (),
           env: dict | None = None, check: bool = True):
    """`scripts/run.sh --no-build --out OUT [args] SCENARIO...` as a user runs it, on the test's
    ports; its output is shown on failure (pytest prints what the test printed). No figures
    unless the test asks for them (COOPNAV_FIGURES: ~1.5 s of CPU a scenario)."""
    import subprocess
    e = dict(os.environ, COOPNAV_RUN_PORT_BASE=str(port), COOPNAV_FIGURES="0")
    e.update(env or {})
    p = subprocess.run(["bash", str(source / "scripts" / "run.sh"), "--no-build", "--out",
                        str(out), *args, *map(str, scenarios)], env=e, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if check and p.returncode != 0:
        print(p.stdout)
        pytest.fail(f"run.sh exited {p.returncode}")
    return p


def scenarios_of(summary: Path) -> dict:
    """summary.json's entries by scenario name."""
    import json
    return {s["scenario"]: s for s in json.loads(Path(summary).read_text())["scenarios"]}


def said_lines(transcript: Path) -> str:
    """The SAY / NOT SAID / ACTION lines of a transcript, to show what a run did."""
    return "\n".join(l for l in Path(transcript).read_text().splitlines()
                     if " SAY " in l or " NOT SAID " in l or " ACTION " in l)


def dialogue_check_failures(s: dict) -> list[str]:
    d = s["dialogue_checks"]
    return [f"{s['scenario']}: {k}: {d[k]}" for k in (
        "action_contradicts_words", "contradictions", "told_twice", "said_to_not_crossing")
        if d[k]]
