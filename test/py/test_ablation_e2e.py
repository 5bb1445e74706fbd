"""The ablation end to end on real processes: 2 generated encounters × 2 variants (the band
planner alone, the paper's system), 2 runs at a time, as a user runs it.

Fails when a run leaves no metrics, when the planner-only runs start an assessor or the dialogue
manager or say anything, when a run lacks its own metrics.json / metrics.csv beside its
summary.json, when a figure is missing, or when tabulating the same folder again does not give
the same bytes."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import yaml

ROOT = Path(os.environ.get("COOPNAV_SOURCE_DIR", Path(__file__).resolve().parents[2]))
BUILD = Path(os.environ.get("COOPNAV_BUILD_DIR", ROOT / "build"))
PORT_BASE = int(os.environ.get("COOPNAV_TEST_PORT_BASE", "7400"))


def coopnav(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, COOPNAV_POP_PORT_BASE=str(PORT_BASE), COOPNAV_BUILD_DIR=str(BUILD))
    p = subprocess.run([sys.executable, str(ROOT / "scripts" / "coopnav"), *args], env=env,
                       capture_output=True, text=True, timeout=300, check=False)
    print(p.stdout[-6000:], p.stderr[-3000:], sep="\n")
    return p


def test_two_encounters_planner_only_against_paper(tmp_path):
    out = tmp_path / "abl"
    p = coopnav("ablation", "--no-build", "--encounters", "2", "--seed", "3", "--variants",
                "paper,planner_only", "-j", "2", "--out", str(out), "--n-boot", "200")
    assert p.returncode == 0, f"ablation exited {p.returncode}"
    doc = json.loads((out / "ablation.json").read_text())
    assert list(doc["result"]["tables"]) == ["planner_only", "paper"]
    assert all(v["missing"] == [] for v in doc["variants"].values())
    assert all(t["runs"] == 2 for t in doc["result"]["tables"].values())
    encounters = json.loads((out / "ablation_plan.json").read_text())["encounters"]
    assert len(encounters) == 2
    for enc in encounters:
        scen = yaml.safe_load((out / "scenarios-planner_only" / f"{enc}.yaml").read_text())
        assert scen["lockstep"]["participants"] == ["band_source"]
        for variant in ("planner_only", "paper"):
            d = out / "runs" / variant / enc
            for f in ("summary.json", "metrics.json", "metrics.csv", "band_source.log"):
                assert (d / f).is_file(), f"{d / f} missing"
        po, pa = out / "runs" / "planner_only" / enc, out / "runs" / "paper" / enc
        for absent in ("situation_assessor", "path_assessor", "dialogue_manager"):
            assert not (po / f"{absent}.log").exists(), f"planner_only started {absent}"
            assert (pa / f"{absent}.log").is_file()
        # Nothing assessed, nothing said: no CM for anyone, no utterance said.
        persons = json.loads((po / "metrics.json").read_text())["runs"][0]["persons"]
        assert all(p.get("cm_interaction_m") is None for p in persons)
        summary = json.loads((po / "summary.json").read_text())["scenarios"][0]
        assert summary["dialogue_checks"]["said"] == 0
    for stem in ("ablation_metrics", "ablation_paired", "agreement_paper"):
        for ext in ("png", "svg"):
            assert (out / f"{stem}.{ext}").stat().st_size > 1000, f"{stem}.{ext}"
    assert not (out / "agreement_planner_only.png").exists()  # no CM without the assessor
    # The paired rows compare the same two encounters.
    rows = [r for r in doc["result"]["paired"] if r["key"] == "success"]
    assert len(rows) == 1 and rows[0]["n_pairs"] == 2 and rows[0]["variant"] == "paper"
    tables = {f: (out / f).read_bytes() for f in ("ablation.json", "ablation.csv", "ablation.md")}
    assert coopnav("ablation", "--aggregate", str(out), "--n-boot", "200",
                   "--no-figures").returncode == 0
    for f, data in tables.items():
        assert (out / f).read_bytes() == data, f"{f} differs when tabulated again"
