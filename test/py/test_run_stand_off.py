"""A mutual wait resolved with words (issue 44), end to end: a 1.9 m corridor with a
late-facilitating person who makes room and waits for the robot docked for them
(test/data/scenarios/corridor_1_9_late_facilitating.yaml). The run must reach the goal without
contact (scripts/run.sh exit 0); summary.json's longest mutual wait must stay under the 10 s a
population counts as a stalemate; the robot must have ended the stand-off in words that were
said ("Thank you, I will go first." or "I will go now.") with a RESUME at the same step; and the
dialogue checks, read from the log alone, must be empty."""

from conftest import dialogue_check_failures, run_sh, said_lines, scenarios_of


def test_a_stand_off_ends_in_words_said_and_done(tmp_path, source_dir, port_base):
    name = "corridor_1_9_late_facilitating"
    run_sh(source_dir, tmp_path, source_dir / "test/data/scenarios" / f"{name}.yaml",
           port=port_base)
    print(said_lines(tmp_path / name / "transcript.txt"))
    s = scenarios_of(tmp_path / "summary.json")[name]
    bad = []
    if s["max_mutual_wait_s"] > 10.0:
        bad.append(f"a mutual wait of {s['max_mutual_wait_s']:.1f} s (over 10 s: a stalemate)")
    said = [(h, e) for h in s["humans"] for e in h["transcript"]
            if e["kind"] == "say" and e["delivery"] == "said"
            and e["act"] in ("INFORM_GOING_FIRST", "INFORM_RESUMING")]
    if not said:
        bad.append("no stand-off ended in words that were said")
    actions = [e for h in s["humans"] for e in h["transcript"] if e["kind"] == "action"]
    for h, e in said:
        if not any(a["action"] == "RESUME" and a["t_s"] == e["t_s"] for a in actions):
            bad.append(f"words to human {h['id']} without a RESUME at the same time: {e}")
    bad += dialogue_check_failures(s)
    d = s["dialogue_checks"]
    print(f"{s['final_state']}, longest mutual wait {s['max_mutual_wait_s']:.1f} s, "
          f"stalled {s['stalled_s']:.1f} s, said {d['said']}")
    assert not bad
