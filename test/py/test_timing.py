"""Where a run's wall time goes (coopnav_exp.timing): log stamps, run_one's phases from its marks
and the world's log, a population's breakdown with and without timing.json, on hand-made
folders."""

import json
import time
from pathlib import Path

import pytest

from coopnav_exp import timing


def stamp(t: float) -> str:
    return time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(t)) + f".{int(round(t % 1 * 1000)):03d}"


def test_stamps_are_read_as_local_wall_time_to_the_millisecond():
    t = 1_800_000_000.25
    assert timing.stamp_s(f"[{stamp(t)}] [coopnav:1] [info] x: ready (pid 1)") == pytest.approx(t)
    assert timing.stamp_s("coopnav_record: recording") is None


def write_world_log(run_dir: Path, running: float, ended: float) -> None:
    (run_dir / "world_sim.log").write_text(
        f"[{stamp(running - 0.1)}] [coopnav:9] [info] world_sim: ready (pid 9)\n"
        f"[{stamp(running)}] [coopnav:9] [info] world_sim: running 'narrow'\n"
        f"[{stamp(ended)}] [coopnav:9] [info] world_sim: 'narrow' ended at t = 40.3 s (step 403)\n")


def test_phases_follow_the_marks_and_the_world_log_and_add_up(tmp_path):
    tl = timing.Timeline()
    t0 = tl.t0 = 1_800_000_000.0
    tl.spawned = {"band_source": t0 + 0.05}
    (tmp_path / "band_source.log").write_text(
        f"[{stamp(t0 + 0.45)}] [coopnav:3] [info] band_source: ready (pid 3)\n")
    tl.marks = {"spawned": t0 + 0.1, "ready": t0 + 0.5, "recorder_ready": t0 + 0.5,
                "world_exited": t0 + 3.0, "after": t0 + 3.0, "stopped": t0 + 3.2,
                "summarized": t0 + 3.5}
    write_world_log(tmp_path, t0 + 0.7, t0 + 2.9)
    doc = tl.write(tmp_path)
    p = doc["phases_s"]
    assert p == pytest.approx({"launch": 0.1, "daemons_ready": 0.4, "recorder_ready": 0.0,
                               "world_ready": 0.2, "simulation": 2.2, "world_exit": 0.1,
                               "after": 0.0, "stop": 0.2, "summarize": 0.3, "other": 0.0},
                              abs=2e-3)
    assert doc["total_s"] == pytest.approx(3.5, abs=2e-3)
    assert doc["ready_s"] == {"band_source": pytest.approx(0.4, abs=2e-3)}
    assert json.loads((tmp_path / "timing.json").read_text()) == doc


def test_a_population_breakdown_with_and_without_timing_files(tmp_path):
    runs, workers = tmp_path / "runs", tmp_path / "workers"
    t0 = 1_800_000_000.0
    # One run from a launcher without timing.json: its worker log's stamps and its world log.
    (runs / "enc_0001").mkdir(parents=True)
    workers.mkdir()
    write_world_log(runs / "enc_0001", t0 + 1.0, t0 + 4.0)
    (workers / "enc_0001.log").write_text(
        f"[{stamp(t0)}] worker: enc_0001 on port 7400\n"
        f"[{stamp(t0 + 6.0)}] worker: enc_0001 done, world_sim exit 0\n")
    b = timing.population_breakdown(tmp_path)
    assert b["runs"] == 1 and not b["detailed"]
    assert b["total_s"] == pytest.approx(6.0, abs=2e-3)
    assert b["phases_s"]["simulation"] == pytest.approx(3.0, abs=2e-3)
    text = timing.format_breakdown(b)
    assert "simulation_share 0.5000" in text and "not simulation" in text
    assert "worker_wall_sum_s 6.000" in text
    # With a timing.json in every run, the detailed phases.
    doc = {"total_s": 4.0, "phases_s": dict.fromkeys(timing.PHASES, 0.0), "ready_s": {"x": 0.5}}
    doc["phases_s"].update(simulation=3.0, daemons_ready=1.0)
    (runs / "enc_0001" / "timing.json").write_text(json.dumps(doc))
    b = timing.population_breakdown(tmp_path)
    assert b["detailed"] and b["ready_mean_s"] == {"x": 0.5}
    text = timing.format_breakdown(b)
    assert "simulation_share 0.7500" in text and "phase_mean_s.daemons_ready 1.0000" in text
    assert timing.format_breakdown(timing.breakdown([])) == "no run timings\n"
