"""run.py: the outcome rules and the arguments (no process), and one run through run_one (the
API every launcher calls): its files, the golden transcript to the byte, a hook that sees the
world stepping, and no process of the run left afterwards."""

import subprocess
from pathlib import Path

import pytest

from conftest import needs_build
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
    assert "--profile must be paper or calibrated, not 'bogus'" in capsys.readouterr().err
    assert cli.main(["run", "--no-build", str(tmp_path / "none.yaml")]) == 2
    assert "no scenario file" in capsys.readouterr().err
    with pytest.raises(SystemExit) as ex:
        cli.main(["run", "--out"])
    assert ex.value.code == 2
    assert "--out needs a value" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_one_run_gives_the_golden_transcript_and_leaves_no_process(tmp_path, source_dir,
                                                                   build_dir, port_base):
    s = system.load()
    needs_build(build_dir, *(s.daemon(n).binary for n in s.names() + ["world_sim"]),
                s.tools["ctl"], s.recorder_binary)
    seen = {}

    def during(live: run.LiveRun) -> None:
        # The hook runs while the world steps: it can wait for a step and see every daemon.
        seen["step5"] = live.ctl("wait-step", "world_sim", "--step", "5", "--timeout-s", "120")
        seen["pids"] = {n: live.pid(n) for n in s.names()}

    def after(live: run.LiveRun) -> None:
        seen["alive_after"] = [n for n in s.names() if live.sup.procs[n].alive()]

    r = run.run_one(source_dir / "config/scenarios/narrow_minimal.yaml", tmp_path / "nm",
                    port_base, during=during, after=after, system=s)
    assert r.ok and r.world_sim_exit == 0 and r.died == []
    assert r.log == tmp_path / "nm/narrow_minimal.lcm" and r.log.is_file()
    assert r.summary == tmp_path / "nm/summary.json"
    assert r.summary_entry()["final_state"] == "GOAL_REACHED"
    assert (tmp_path / "nm/scenario.path").read_text().strip() == \
        str(source_dir / "config/scenarios/narrow_minimal.yaml")
    for n in s.names() + ["world_sim"]:
        assert (tmp_path / "nm" / f"{n}.log").is_file(), n
    assert seen["step5"] == 0 and seen["alive_after"] == s.names()
    for n, pid in seen["pids"].items():
        assert not Path(f"/proc/{pid}").exists() or \
            Path(f"/proc/{pid}/stat").read_text().split()[2] == "Z", f"{n} still running"
    transcript = subprocess.run([str(s.tool("ctl")), "transcript", str(r.log), "--scenario",
                                 "narrow_minimal"], stdout=subprocess.PIPE, check=True).stdout
    assert transcript == (source_dir / "test/data/golden/narrow_minimal.transcript").read_bytes()
