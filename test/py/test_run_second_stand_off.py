"""A second stand-off after a dock ended, resolved with words (issue 44), end to end: a 1.8 m
corridor with a person standing in the robot's way (test/data/scenarios/
corridor_1_8_second_stand_off.yaml). The robot docks, the person does not come, the dock ends
with words ("I will go now."); the two meet again and wait. That second stand-off must be
resolved by a DOCK said in the same step (never silence), the run must reach the goal without
contact (scripts/run.sh exit 0), no mutual wait may last 10 s, and the dialogue checks, read from
the log alone, must be empty."""

from conftest import dialogue_check_failures, run_sh, said_lines, scenarios_of

MAKING_ROOM = ("INFORM_DOCKING", "INFORM_WIDER_PLACE", "INFORM_RETREAT", "INFORM_STOPPING")


def test_a_second_stand_off_is_resolved_with_words(tmp_path, source_dir, port_base):
    name = "corridor_1_8_second_stand_off"
    run_sh(source_dir, tmp_path, source_dir / "test/data/scenarios" / f"{name}.yaml",
           port=port_base)
    print(said_lines(tmp_path / name / "transcript.txt"))
    s = scenarios_of(tmp_path / "summary.json")[name]
    events = [e for h in s["humans"] for e in h["transcript"]]
    said = [e for e in events if e["kind"] == "say" and e["delivery"] == "said"]
    actions = [e for e in events if e["kind"] == "action"]
    bad = []
    if s["max_mutual_wait_s"] > 10.0:
        bad.append(f"a mutual wait of {s['max_mutual_wait_s']:.1f} s (over 10 s: a stalemate)")
    # The first dock ends with words and a RESUME in the same step ...
    resumed = [e for e in said if e["act"] in ("INFORM_RESUMING", "INFORM_GOING_FIRST")
               and any(a["action"] == "RESUME" and a["t_s"] == e["t_s"] for a in actions)]
    if not resumed:
        bad.append("no dock ended in words that were said with a RESUME")
    # ... and a later stand-off makes room again, said in the step of its DOCK.
    first_resume_t = min((e["t_s"] for e in resumed), default=float("inf"))
    again = [e for e in said if e["act"] in MAKING_ROOM and e["t_s"] > first_resume_t
             and any(a["action"] == "DOCK" and a["t_s"] == e["t_s"] for a in actions)]
    if not again:
        bad.append("the stand-off after the dock ended was not resolved by a DOCK with words")
    bad += dialogue_check_failures(s)
    d = s["dialogue_checks"]
    print(f"{s['final_state']}, longest mutual wait {s['max_mutual_wait_s']:.1f} s, "
          f"stalled {s['stalled_s']:.1f} s, said {d['said']}")
    assert not bad
