"""One kinematics (issue 44), end to end as a user runs it: the paper's narrow_minimal with a
differential-drive robot (config/scenarios/narrow_minimal.yaml with robot.kinematics:
differential). With the band source forced to plan holonomic bands (--set
planner.robot.holonomic=true after what the launch derives from the scenario: config/system.yaml's
holonomic_key), world_sim refuses the run before the first step and scripts/run.sh exits non-zero
naming both settings. Run as it comes, the launch gives the band source the scenario's kinematics
and the robot passes the minimal person by turning and docking: the goal is reached without
contact, and run.sh exits 0."""

import re

import yaml

from conftest import run_sh, scenarios_of

NAME = "narrow_minimal_differential"


def test_a_kinematics_mismatch_is_refused_and_a_differential_robot_passes(
        tmp_path, source_dir, port_base):
    src = source_dir / "config/scenarios/narrow_minimal.yaml"
    doc = yaml.safe_load(src.read_text())
    doc["name"] = NAME
    doc["map"]["file"] = str((src.parent / doc["map"]["file"]).resolve())
    assert doc["robot"]["kinematics"] == "holonomic"
    doc["robot"]["kinematics"] = "differential"
    scenario = tmp_path / f"{NAME}.yaml"
    scenario.write_text(yaml.safe_dump(doc, sort_keys=False))

    p = run_sh(source_dir, tmp_path / "mismatch", scenario, port=port_base, check=False,
               env={"COOPNAV_DAEMON_ARGS_band_source": "--set planner.robot.holonomic=true"})
    assert p.returncode != 0, f"a differential scenario under a holonomic band source ran:\n{p.stdout}"
    # The refusal names both settings (world_sim's message, passed on by run.sh).
    assert re.search(r"robot\.kinematics is differential.*planner\.robot\.holonomic: true",
                     p.stdout), p.stdout
    print(f"mismatch refused (run.sh exit {p.returncode})")

    p = run_sh(source_dir, tmp_path / "diff", scenario, port=port_base + 10, check=False)
    transcript = tmp_path / "diff" / NAME / "transcript.txt"
    print(transcript.read_text() if transcript.is_file() else p.stdout)
    s = scenarios_of(tmp_path / "diff" / "summary.json")[NAME]
    print(f"differential narrow_minimal: {s['final_state']}, min clearance "
          f"{s['min_clearance_m']}, docks {s.get('docks')}, retreats {s.get('retreats')}, time "
          f"to goal {s['robot_time_to_goal_s']}")
    assert s["final_state"] == "GOAL_REACHED", s["detail"]
    assert not s.get("contact")
    assert p.returncode == 0, p.stdout
