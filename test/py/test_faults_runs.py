"""Faults, shortened (README "Faults"; the full run is scripts/faults.sh): the four paper
scenarios, each run clean, with one daemon killed (-9) at a seeded random step and started again
with its journal, and under 10 % message loss; narrow_minimal also without the distance server
for the whole run (it collided before the precautionary dock: it must end without a collision,
docking as a precaution). Each run must complete with the clean run's decisions (or say that
they are degraded), never a dock the clean run did not have unless it is a precaution, never a
daemon dying on its own; under loss the decisions must be the clean ones exactly.
Selection (13 runs): one kill per scenario, the daemons with state to recover (the distance
server is stateless: its absence is the absent run); the loss runs of all four scenarios."""

import os
import subprocess


def test_faults_shortened(tmp_path, source_dir, port_base):
    p = subprocess.run(
        ["bash", str(source_dir / "scripts/faults.sh"), "--no-build", "--out", str(tmp_path / "a"),
         "--scenarios", "open_facilitating open_minimal narrow_facilitating narrow_minimal",
         "--kill", "situation_assessor dialogue_manager path_assessor band_source",
         "--kills-per-scenario", "1", "--absent-in", "narrow_minimal", "--seed", "7"],
        env=dict(os.environ, COOPNAV_FAULT_PORT_BASE=str(port_base)), stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT, text=True)
    print(p.stdout)
    if p.returncode != 0:
        for f in sorted(tmp_path.glob("a/*/*/world_sim.log")):
            print(f"--- {f}\n" + "\n".join(f.read_text().splitlines()[-3:]))
    assert p.returncode == 0
    lines = (tmp_path / "a/faults.txt").read_text().splitlines()
    assert len(lines) == 13
