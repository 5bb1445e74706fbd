"""A guard that sees what the map does not, end to end through scripts/run.sh: a box stands in
open.pgm's 2.25 m corridor, in the robot's way, and is not on the robot's map; only world_sim's
simulated laser (COOPNAV_SCAN) shows it to the band source.
Where there is no room beside a box, the robot holds short of it on its static path: a unit test
(DualBandPlannerTest.ObstaclePointsTheRobotCannotPassHoldItOnTheStaticPath) shows it; the
scenario test/data/scenarios/unmapped_box_blocked.yaml runs it end to end by hand (open.pgm offers
a way round through the parallel corridor, which the robot takes: it never squeezes at the gap).

1. unmapped_box_corridor, the box alone, 1.4 m free beside it: the robot's global path, planned
   again round the laser's returns, goes round the box; it reaches its goal (run.sh exit 0) with
   no collision and a clearance > 0 from the box.
2. unmapped_box_encounter, the box where the robot meets a minimal human whose lane is the way
   round: no collision, no contact with the human, clearance > 0 from the box, and both reach
   their goals (exit 0).
3. The control: the first scenario with the laser off (world_sim --set laser=off): the robot,
   blind to the box, drives into it (the run ends in COLLISION). So the first run's clearance is
   the scan's doing.

The clearance to the box is the recorded robot's (`coopnav_ctl trace`: its centre and radius at
every step) against the scenario's `unmapped_obstacles`, as world_sim measures it: the distance
from the robot's centre to the nearest point of a box (or circle) less the radii.
"""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import yaml

from conftest import run_sh, scenarios_of
from coopnav_exp import system


def unmapped_clearance_m(scenario: Path, run_dir: Path, log: Path) -> float:
    """The robot's least clearance to the scenario's unmapped obstacles over the recorded run."""
    obstacles = yaml.safe_load(scenario.read_text())["unmapped_obstacles"]
    trace = run_dir / "trace.json"
    subprocess.run([str(system.load().tool("ctl")), "trace", str(log), "--json", str(trace)],
                   check=True)
    robot = json.loads(trace.read_text())["robot"]
    r = robot["radius_m"]
    least = math.inf
    for x, y in zip(robot["x_m"], robot["y_m"]):
        if x is None or y is None:
            continue
        for b in obstacles.get("boxes", []):
            cx = min(max(x, b["min_x_m"]), b["max_x_m"])
            cy = min(max(y, b["min_y_m"]), b["max_y_m"])
            least = min(least, math.hypot(x - cx, y - cy) - r)
        for c in obstacles.get("circles", []):
            least = min(least, math.hypot(x - c["x_m"], y - c["y_m"]) - c["radius_m"] - r)
    return least


def run_box(source_dir: Path, out: Path, name: str, port: int, expected_rc: int,
            world_args: str = "") -> tuple[dict, float]:
    """run.sh on test/data/scenarios/NAME.yaml: its summary entry and its clearance to the box.
    run.sh exits 3 when a run ends in a contact, a standstill or the time limit: the blind
    control (a collision) expects it, the others 0."""
    scenario = source_dir / "test/data/scenarios" / f"{name}.yaml"
    p = run_sh(source_dir, out, scenario, port=port, check=False,
               env={"COOPNAV_DAEMON_ARGS_world_sim": world_args})
    if p.returncode != expected_rc:
        print(p.stdout)
    assert p.returncode == expected_rc, f"run.sh {name} exited {p.returncode}, not {expected_rc}"
    s = scenarios_of(out / "summary.json")[name]
    clearance = unmapped_clearance_m(scenario, out / name, out / name / f"{name}.lcm")
    print(f"{name} {world_args}: {s['final_state']} at t = {s['sim_time_s']} s ({s['detail']}); "
          f"clearance to the box {clearance:.3f} m, to a human {s.get('min_clearance_m')} m")
    return s, clearance


def test_the_box_alone_is_gone_round(tmp_path, source_dir, port_base):
    s, clearance = run_box(source_dir, tmp_path / "box", "unmapped_box_corridor", port_base, 0)
    assert not s["collision"], s["detail"]
    assert clearance > 0.0
    assert s["final_state"] == "GOAL_REACHED", "the robot should go round the box to its goal"


def test_the_box_and_a_person(tmp_path, source_dir, port_base):
    s, clearance = run_box(source_dir, tmp_path / "enc", "unmapped_box_encounter",
                           port_base + 20, 0)
    print((tmp_path / "enc/unmapped_box_encounter/transcript.txt").read_text())
    assert not s["collision"], s["detail"]
    assert s["contact"] is None, f"contact with the human: {s['contact']}"
    assert clearance > 0.0
    assert s["final_state"] == "GOAL_REACHED", "the robot should go round the box to its goal"


def test_without_the_scan_the_robot_drives_into_the_box(tmp_path, source_dir, port_base):
    s, _ = run_box(source_dir, tmp_path / "blind", "unmapped_box_corridor", port_base + 40, 3,
                   "--set laser=off")
    assert s["final_state"] == "COLLISION" or s["collision"], \
        f"the blind robot did not hit the box: {s['final_state']} ({s['detail']})"
