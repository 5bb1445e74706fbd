"""run.py without a process: the outcome rules, the extra arguments from the environment, bad
arguments refused before any run. run_one itself: test_run_mechanics.py (stand-ins) and the
e2e tests of real runs (test_run_paper_scenarios.py: the golden transcript to the byte)."""

import pytest

from coopnav_exp import cli, run, system


def test_outcome_failure_names_what_went_wrong():
    assert run.outcome_failure({"final_state": "GOAL_REACHED", "contact": None}) is None
    assert run.outcome_failure(None) == "no readable summary"
    assert run.outcome_failure({"final_state": "STANDSTILL", "sim_time_s": 41.0,
                                "detail": "no progress"}) == \
        "STANDSTILL at t = 41.0 s: no progress"
    assert run.outcome_failure({"final_state": "COLLISION", "collision": True,
                                "contact": {"human_id": 2, "t_s": 9.5, "robot_at_fault": True}}) \
        == "contact with human 2 at t = 9.5 s (robot at fault)"
    assert run.outcome_failure({"final_state": "GOAL_REACHED",
                                "contact": {"human_id": 1, "t_s": 3.0}}) == \
        "contact with human 1 at t = 3.0 s (robot not at fault)"
    assert run.outcome_failure({"final_state": "PARTICIPANT_TIMEOUT"}) == \
        "final state PARTICIPANT_TIMEOUT"


def test_outcome_command_exits_1_unless_every_run_reached_its_goals(tmp_path, capsys):
    import json
    good = {"scenario": "narrow_minimal", "final_state": "GOAL_REACHED", "contact": None}
    bad = {"scenario": "open_minimal", "final_state": "TIME_LIMIT", "sim_time_s": 60.0}
    f = tmp_path / "summary.json"
    f.write_text(json.dumps({"format": "coopnav-summary/1", "scenarios": [good]}))
    assert cli.main(["outcome", str(f)]) == 0
    assert capsys.readouterr().out == "narrow_minimal GOAL_REACHED\n"
    f.write_text(json.dumps({"format": "coopnav-summary/1", "scenarios": [good, bad]}))
    assert cli.main(["outcome", str(f)]) == 1
    assert "open_minimal TIME_LIMIT: TIME_LIMIT at t = 60.0 s" in capsys.readouterr().out
    f.write_text("{}")
    assert cli.main(["outcome", str(f)]) == 1
    assert cli.main(["outcome", str(tmp_path / "none.json")]) == 1


def test_daemon_args_from_the_environment():
    s = system.load()
    env = {"COOPNAV_DAEMON_ARGS_band_source": " --set a=1  --set b=2 ",
           "COOPNAV_DAEMON_ARGS_world_sim": "--set retransmit_period_s=0.02",
           "COOPNAV_DAEMON_ARGS_path_assessor": "  ", "COOPNAV_DAEMON_ARGS_ghost": "--x"}
    assert run.daemon_args_from_env(s, env) == {
        "band_source": ["--set", "a=1", "--set", "b=2"],
        "world_sim": ["--set", "retransmit_period_s=0.02"]}


def test_bad_arguments_exit_2_before_any_run(tmp_path, capsys):
    assert cli.main(["run", "--no-build", "--profile", "bogus", "--out", str(tmp_path / "o")]) == 2
    assert "--profile must be paper, calibrated, forecast or make_time, not 'bogus'" in capsys.readouterr().err
    assert cli.main(["run", "--no-build", str(tmp_path / "none.yaml")]) == 2
    assert "no scenario file" in capsys.readouterr().err
    with pytest.raises(SystemExit) as ex:
        cli.main(["run", "--out"])
    assert ex.value.code == 2
    assert "--out needs a value" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()

