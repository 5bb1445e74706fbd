"""Safe passage end to end, as a user runs it: scripts/run.sh on a 1.8 m corridor with a
minimally contributing human (test/data/scenarios/corridor_1_8_minimal.yaml). The robot must
make room that is really room, and the run must end without any contact: no collision, no
contact in summary.json, and whatever the robot said about making room is what it did."""

from conftest import run_sh, scenarios_of


def test_a_minimal_human_in_1_8_m_is_passed_without_contact(tmp_path, source_dir, port_base):
    name = "corridor_1_8_minimal"
    run_sh(source_dir, tmp_path, source_dir / "test/data/scenarios" / f"{name}.yaml",
           port=port_base)
    print((tmp_path / name / "transcript.txt").read_text())
    s = scenarios_of(tmp_path / "summary.json")[name]
    print(f"outcome {s.get('outcome')}, min clearance {s.get('min_clearance_m')} m, docks "
          f"{s.get('docks')}, retreats {s.get('retreats')}, guard steps {s.get('guard_steps')}")
    bad = []
    if s["collision"]:
        bad.append(f"collision: {s['detail']}")
    if s.get("contact"):
        bad.append(f"contact: {s['contact']}")
    if s.get("outcome") not in (None, "GOAL_REACHED", "STANDSTILL"):
        bad.append(f"outcome {s.get('outcome')}")
    assert not bad
