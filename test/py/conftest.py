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


def needs_build(build: Path, *relative: str) -> None:
    """Skips nothing: a test that needs built binaries fails if they are missing."""
    missing = [r for r in relative if not (build / r).exists()]
    if missing:
        pytest.fail(f"not built in {build}: {', '.join(missing)}")
