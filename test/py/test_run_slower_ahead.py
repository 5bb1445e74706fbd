"""A slower walker ahead followed, then passed with words (issue 44), end to end: a 3.0 m corridor
with a person walking the robot's way at 0.5 m/s, 0.4 m off the centre line (test/data/
scenarios/corridor_3_0_slower_ahead.yaml). The robot must follow them (the band source's log),
say "Excuse me, I will pass on your right." to them (the structured transcript of summary.json),
pass them only once the words are said (GO_FIRST for them, decided "overtake:", at or after the
words' end), on the side it named, and reach its goal ahead of them without contact
(scripts/run.sh exit 0); no stall, no mutual wait, the dialogue checks read from the log empty."""

from conftest import dialogue_check_failures, run_sh, said_lines, scenarios_of


def test_a_slower_walker_is_followed_then_passed_with_words(tmp_path, source_dir, port_base):
    name = "corridor_3_0_slower_ahead"
    run_sh(source_dir, tmp_path, source_dir / "test/data/scenarios" / f"{name}.yaml",
           port=port_base)
    print(said_lines(tmp_path / name / "transcript.txt"))
    s = scenarios_of(tmp_path / "summary.json")[name]
    events = [e for h in s["humans"] for e in h["transcript"]]
    said = [e for e in events if e["kind"] == "say" and e["delivery"] == "said"]
    actions = [e for e in events if e["kind"] == "action"]
    band_log = (tmp_path / name / "band_source.log").read_text()
    bad = []
    if s["final_state"] != "GOAL_REACHED":
        bad.append(f"the run ended {s['final_state']}")
    following = band_log.find("following human 1 (ahead, walking the robot's way)")
    passing = band_log.find("passing human 1 on their right")
    passed = band_log.find("passing human 1 ends at step")
    if not 0 <= following < passing < passed:
        bad.append("the band source did not follow human 1, then pass them on their right")
    if "the person is passed" not in band_log[passed:passed + 120]:
        bad.append("the pass did not end with the person passed")
    words = [e for e in said if e["act"] == "INFORM_DIRECTION"
             and e["text"] == "Excuse me, I will pass on your right."]
    if len(words) != 1:
        bad.append(f"the pass was announced {len(words)} times, not once")
    go = [a for a in actions if a["action"] == "GO_FIRST"]
    if len(go) != 1 or "overtake:" not in go[0]["reason"]:
        bad.append(f"not one GO_FIRST decided on the overtake: {go}")
    elif words and go[0]["t_s"] + 1e-9 < (words[0]["t_s"] + words[0]["speech_start_s"]
                                           + words[0]["speech_duration_s"]):
        bad.append("the robot was sent past before its words were said")
    if s["max_mutual_wait_s"] > 0.0 or s["stalled_s"] > 3.0:
        bad.append(f"stalled {s['stalled_s']:.1f} s, mutual wait {s['max_mutual_wait_s']:.1f} s")
    bad += dialogue_check_failures(s)
    print(f"{s['final_state']}, time to goal {s['robot_time_to_goal_s']}, stalled "
          f"{s['stalled_s']:.1f} s, min clearance {s['min_clearance_m']:.2f} m")
    assert not bad, bad
