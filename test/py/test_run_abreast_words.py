"""Words that match actions (issue 44), end to end as a user runs it: two people walking abreast
towards the robot in a 2.5 m corridor (test/data/scenarios/abreast_2_5_minimal.yaml). The run
must reach the goal without contact (scripts/run.sh exit 0), and summary.json's dialogue checks,
read from the log alone, must be empty: no action contradicting the words (a dock after "I am
passing on your right." without words of making room), no group told two sides or the same
round twice, nothing said to someone not being crossed."""

from conftest import dialogue_check_failures, run_sh, said_lines, scenarios_of


def test_two_abreast_hear_words_that_match_the_actions(tmp_path, source_dir, port_base):
    name = "abreast_2_5_minimal"
    run_sh(source_dir, tmp_path, source_dir / "test/data/scenarios" / f"{name}.yaml",
           port=port_base)
    print(said_lines(tmp_path / name / "transcript.txt"))
    s = scenarios_of(tmp_path / "summary.json")[name]
    d = s["dialogue_checks"]
    print(f"{s['final_state']}, said {d['said']}, action_words_too_late "
          f"{d['action_words_too_late']}")
    bad = dialogue_check_failures(s)
    if d["said"] == 0:
        bad.append("nothing said to the pair")
    assert not bad
