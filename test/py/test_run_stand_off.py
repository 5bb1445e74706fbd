"""A stand-off resolved with words (issue 44), end to end: a 1.7 m corridor where the robot,
unable to let a facilitating person by where it drives, backs off before them with no crossing
ahead (test/data/scenarios/corridor_1_7_backing_off.yaml). The run must reach the goal without
contact (scripts/run.sh exit 0); summary.json's longest mutual wait must stay under the 10 s a
population counts as a stalemate; the robot must have ended the stand-off with a decision said
and done in the same step (words that were said, and the robot action the stand-off's round
reason names); and the dialogue checks, read from the log alone, must be empty."""

from conftest import dialogue_check_failures, run_sh, said_lines, scenarios_of


def test_a_stand_off_ends_in_words_said_and_done(tmp_path, source_dir, port_base):
    name = "corridor_1_7_backing_off"
    run_sh(source_dir, tmp_path, source_dir / "test/data/scenarios" / f"{name}.yaml",
           port=port_base)
    print(said_lines(tmp_path / name / "transcript.txt"))
    s = scenarios_of(tmp_path / "summary.json")[name]
    bad = []
    if s["max_mutual_wait_s"] > 10.0:
        bad.append(f"a mutual wait of {s['max_mutual_wait_s']:.1f} s (over 10 s: a stalemate)")
    events = [e for h in s["humans"] for e in h["transcript"]]
    resolved = [e for e in events if e["kind"] == "action" and "stand-off" in e["reason"]]
    if not resolved:
        bad.append("no robot action ended a stand-off")
    for a in resolved:
        if not any(e["kind"] == "say" and e["delivery"] == "said" and e["t_s"] == a["t_s"]
                   for e in events):
            bad.append(f"a stand-off ended without words said in the same step: {a}")
    bad += dialogue_check_failures(s)
    d = s["dialogue_checks"]
    print(f"{s['final_state']}, longest mutual wait {s['max_mutual_wait_s']:.1f} s, "
          f"stalled {s['stalled_s']:.1f} s, said {d['said']}")
    assert not bad
