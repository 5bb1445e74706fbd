"""coopnav_exp.population and .slurm without processes: the runs a folder holds, the progress line,
the Slurm slices and ports."""

from __future__ import annotations

import io
from pathlib import Path

from coopnav_exp import pool, population, slurm


def write_jobs(tmp_path: Path) -> Path:
    (tmp_path / "jobs.txt").write_text(
        "base_w2\tscenarios/base_w2.yaml\n"
        "pop_0001\tscenarios/pop_0001.yaml\n"
        "pop_0001_muted\tscenarios/pop_0001.yaml\tmuted\n")
    return tmp_path


def test_run_specs_follow_jobs_txt(tmp_path):
    out = write_jobs(tmp_path)
    options = population.RunOptions("calibrated", tuple(population.GOALS_WITHHELD_ARGS), 60.0)
    specs = population.run_specs(out, options)
    assert [s.name for s in specs] == ["base_w2", "pop_0001", "pop_0001_muted"]
    # A muted twin runs its encounter's file with the dialogue manager muted.
    assert specs[2].scenario == out / "scenarios" / "pop_0001.yaml"
    assert specs[2].daemon_args["dialogue_manager"] == ["--set", "muted=true"]
    assert "dialogue_manager" not in specs[1].daemon_args
    # Every run writes what its humans heard next to its summary (the aggregation reads it).
    world = specs[1].daemon_args["world_sim"]
    assert world[:2] == ["--set", "publish_human_goals=false"]
    assert world[-1] == f"cue_outcomes_file={out / 'runs' / 'pop_0001' / 'cue_outcomes.jsonl'}"
    assert all(s.profile == "calibrated" and s.timeout_s == 60.0 for s in specs)
    # What a worker process gets back is what was given.
    assert population.RunSpec.from_json(specs[2].to_json()) == specs[2]


def test_summary_state(tmp_path):
    assert population.summary_state(tmp_path) == ("NO_SUMMARY", None)
    (tmp_path / "summary.json").write_text(
        '{"scenarios": [{"final_state": "GOAL_REACHED", "sim_time_s": 41.25}]}')
    assert population.summary_state(tmp_path) == ("GOAL_REACHED", 41.25)
    (tmp_path / "summary.json").write_text('{"scenarios": []}')
    assert population.summary_state(tmp_path) == ("NO_SUMMARY", None)


def test_progress_line_is_population_sh_s():
    p = pool.Progress(26, io.StringIO(), start_s=0.0)
    line = p.line(12, "pop_0007", "GOAL_REACHED", 41.2, 9.3, now_s=96.0)
    # 96 s for 12 runs: 8 s a run, 14 left.
    assert line == ("[12/26] pop_0007         GOAL_REACHED        sim 41.2 s   wall    9.3 s  "
                    "ETA 1m52s")
    assert p.line(1, "base_w2", "NO_SUMMARY", None, 900.0, now_s=900.0).endswith(
        "NO_SUMMARY          sim -        wall  900.0 s  ETA 375m00s")
    s = io.StringIO()
    q = pool.Progress(2, s, start_s=0.0)
    q.show(1, "a", "GOAL_REACHED", 1.0, 1.0)
    q.end()
    assert "\r" not in s.getvalue() and s.getvalue().count("\n") == 1  # piped: a line each


def test_slurm_slices_cover_every_run_once():
    for n, tasks in ((1, 1), (7, 3), (26, 4), (10, 10)):
        seen = sorted(i for t in range(tasks) for i in slurm.task_slice(n, tasks, t))
        assert seen == list(range(n))
    assert slurm.task_slice(7, 3, 1) == [1, 4]


def test_slurm_tasks_have_ports_of_their_own():
    firsts = [slurm.task_ports(7400, t, 4) for t in range(100)]
    ports = {f + s for f in firsts for s in range(4)}
    assert len(ports) == 400
    assert all(7400 <= p < 7400 + slurm.PORT_SPAN for p in ports)


def test_slurm_job_script_runs_a_task(tmp_path):
    text = slurm.job_script(tmp_path)
    assert text.startswith("#!/bin/bash\n")
    assert f"-m coopnav_exp.slurm task {tmp_path}\n" in text
    assert "export PYTHONPATH=" in text and "export COOPNAV_BUILD_DIR=" in text
