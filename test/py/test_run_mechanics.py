"""run_one's mechanics with stand-in processes (no daemon, no build): the order processes start
in, each command line (profile, journal, extra arguments, loss relays, absent daemons), the
hooks, a daemon dying at start, world_sim's exit status and timeout, and nothing left running.
The stand-ins log their argv and act as their role does (a recorder writes its file, coopnav_ctl
answers wait-ready, summarize and metrics)."""

import json
import os
import shutil
import stat
import time
from pathlib import Path

import pytest
import yaml

from coopnav_exp import run, system

FAKE = r'''#!/usr/bin/python3
import json, os, signal, sys, time
from pathlib import Path
name = Path(sys.argv[0]).name
log = Path(os.environ["FAKE_DIR"])
with open(log / "argv.jsonl", "a") as f:
    f.write(json.dumps([name, time.monotonic(), os.getpid()] + sys.argv[1:]) + "\n")
signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
if name == "coopnav_ctl":
    if sys.argv[1] == "summarize":
        out = sys.argv[sys.argv.index("--out") + 1]
        # A run without the distance server: its situations say the distances are unknown.
        unknown = 5 if "absent" in out else 0
        Path(out).write_text(json.dumps({"scenarios": [{
            "final_state": "GOAL_REACHED", "sim_time_s": 1.0,
            "faults": {"crossing_distance_unknown": unknown}}]}))
    if sys.argv[1] == "metrics":
        out = sys.argv[sys.argv.index("--json") + 1]
        Path(out).write_text(json.dumps({"format": "coopnav-metrics/1", "runs": []}))
    if sys.argv[1] == "wait-ready":
        if "--announce" in sys.argv:
            print("listening", flush=True)
        time.sleep(float(os.environ.get("FAKE_READY_S", "0.2")))
    sys.exit(0)
if name == "coopnav_world_sim":
    time.sleep(float(os.environ.get("FAKE_WORLD_S", "0.3")))
    sys.exit(int(os.environ.get("FAKE_WORLD_EXIT", "0")))
if name == "coopnav_record":
    print(f"coopnav_record: recording '{sys.argv[3]}' into {sys.argv[-1]}", flush=True)
    Path(sys.argv[-1]).write_bytes(b"log")
if name == os.environ.get("FAKE_DIE", ""):
    print("bad map: resolution_m", flush=True)
    sys.exit(3)
while True:
    time.sleep(1)
'''


@pytest.fixture
def fake(tmp_path, monkeypatch, source_dir):
    """A system whose every binary is the stand-in, in a build folder of the test's own."""
    build = tmp_path / "build"
    s = system.load()
    rels = [s.daemon(n).binary for n in s.names() + ["world_sim"]] + list(s.tools.values()) + [
        s.recorder_binary]
    for rel in rels:
        p = build / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(FAKE)
        p.chmod(p.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("COOPNAV_BUILD_DIR", str(build))
    monkeypatch.setenv("FAKE_DIR", str(tmp_path))
    scenario = tmp_path / "scen.yaml"
    shutil.copy(source_dir / "config/scenarios/narrow_minimal.yaml", scenario)
    return s, scenario


def calls(tmp_path):
    return [json.loads(l) for l in (tmp_path / "argv.jsonl").read_text().splitlines()]


def gone(pid):
    try:
        return Path(f"/proc/{pid}/stat").read_text().split()[2] == "Z"
    except OSError:
        return True


def test_start_order_command_lines_hooks_and_nothing_left(fake, tmp_path):
    s, scenario = fake
    seen = []
    r = run.run_one(scenario, tmp_path / "o", 41000, profile="calibrated", state=True,
                    daemon_args={"band_source": ["--set", "a=1"]},
                    absent=("obstacle_distance_server",), system=s,
                    during=lambda live: seen.append(("during", live.sup.procs["world_sim"].alive())),
                    after=lambda live: seen.append(("after", live.sup.procs["world_sim"].alive())))
    assert r.ok and r.world_sim_exit == 0 and r.died == []
    assert r.summary == tmp_path / "o/summary.json" and r.summary_entry()["sim_time_s"] == 1.0
    assert seen == [("during", True), ("after", False)]
    c = calls(tmp_path)
    names = sorted(x[0] for x in c)
    # The recorder, wait-ready (listening before the daemons start: it hears each one's first
    # status), the daemons (the absent one not), the world once they are ready, then summarize
    # and the metrics (scored with the scenario as the map).
    assert names == sorted(["coopnav_record", "coopnav_band_source", "coopnav_situation_assessor",
                            "coopnav_path_assessor", "coopnav_dialogue_manager", "coopnav_ctl",
                            "coopnav_world_sim", "coopnav_ctl", "coopnav_ctl"])
    t = {(x[0], x[3] if x[0] == "coopnav_ctl" else ""): x[1] for x in c}
    assert t[("coopnav_ctl", "wait-ready")] < t[("coopnav_band_source", "")] < \
        t[("coopnav_world_sim", "")] < \
        t[("coopnav_ctl", "summarize")] < t[("coopnav_ctl", "metrics")]
    scored = next(x for x in c if x[0] == "coopnav_ctl" and x[3] == "metrics")
    assert scored[4:] == [str(tmp_path / "o/scen.lcm"), "--map", str(scenario), "--json",
                          str(tmp_path / "o/metrics.json"), "--csv",
                          str(tmp_path / "o/metrics.csv")]
    assert r.metrics == tmp_path / "o/metrics.json"
    ready = next(x for x in c if x[0] == "coopnav_ctl" and x[3] == "wait-ready")
    assert ready[4:] == ["band_source", "situation_assessor", "path_assessor",
                         "dialogue_manager", "--timeout-s", "60", "--announce"]
    # Where the wall time went: phases that add up to the run's, the world's fake waits in them
    # (FAKE_READY_S 0.2 to be ready, FAKE_WORLD_S 0.3 to run; the fake world logs no stamps,
    # so its start, run and exit are one: world_exit).
    tm = json.loads((tmp_path / "o/timing.json").read_text())
    assert abs(sum(tm["phases_s"].values()) - tm["total_s"]) < 0.01
    assert tm["phases_s"]["launch"] + tm["phases_s"]["daemons_ready"] >= 0.15
    assert tm["phases_s"]["world_exit"] >= 0.25
    by = {x[0]: x[3:] for x in c}
    url = run.lcm_url(41000)
    st = str(tmp_path / "o/state")
    assert by["coopnav_band_source"] == [
        "-c", str(s.config_dir / "band_source.yaml"), "--set", f"map_file={scenario}",
        "--set", "planner.robot.holonomic=true", "--state-dir", st, "--set", "a=1",
        "--lcm-url", url]
    assert by["coopnav_path_assessor"] == [
        "-c", str(s.config_dir / "path_assessor_calibrated.yaml"), "--state-dir", st,
        "--lcm-url", url]
    assert by["coopnav_world_sim"] == ["-c", str(s.config_dir / "world_sim.yaml"), "--set",
                                       f"scenario={scenario}", "--lcm-url", url]
    assert by["coopnav_record"] == ["-f", "-c", "COOPNAV_.*", "--lcm-url", url,
                                    str(tmp_path / "o/scen.lcm")]
    for x in c:
        assert gone(x[2]), f"{x[0]} still running"
    for n in ("band_source", "world_sim", "record"):
        assert (tmp_path / "o" / f"{n}.log").is_file()


def test_loss_puts_each_process_on_a_port_of_its_own_behind_the_relay(fake, tmp_path):
    s, scenario = fake
    r = run.run_one(scenario, tmp_path / "o", 41000, loss=0.1, loss_seed=5, system=s)
    assert r.ok
    by = {x[0]: x[3:] for x in calls(tmp_path)}
    relay = by["coopnav_lossy_relay"]
    eps = [relay[i + 1] for i, a in enumerate(relay) if a == "--endpoint"]
    assert eps == [run.lcm_url(41001 + i) for i in range(6)]
    assert relay[-6:] == ["--lossless", run.lcm_url(41000), "--loss", "0.1", "--seed", "5"]
    assert by["coopnav_dialogue_manager"][-1] == run.lcm_url(41005)
    assert by["coopnav_world_sim"][-1] == run.lcm_url(41006)
    assert by["coopnav_record"][4] == run.lcm_url(41000)


def test_a_daemon_dying_at_start_is_said_at_once(fake, tmp_path, monkeypatch, capsys):
    s, scenario = fake
    monkeypatch.setenv("FAKE_DIE", "coopnav_path_assessor")
    monkeypatch.setenv("FAKE_READY_S", "30")
    t0 = time.monotonic()
    r = run.run_one(scenario, tmp_path / "o", 41000, system=s)
    assert time.monotonic() - t0 < 10
    assert not r.ok and r.world_sim_exit == 1
    err = capsys.readouterr().err
    assert "path_assessor exited at start (status 3)" in err
    assert "path_assessor: bad map: resolution_m" in err
    assert "coopnav_world_sim" not in [x[0] for x in calls(tmp_path)]
    for x in calls(tmp_path):
        assert gone(x[2]), f"{x[0]} still running"


def test_world_exit_status_and_timeout(fake, tmp_path, monkeypatch):
    s, scenario = fake
    monkeypatch.setenv("FAKE_WORLD_EXIT", "4")
    assert run.run_one(scenario, tmp_path / "a", 41000, system=s).world_sim_exit == 4
    monkeypatch.setenv("FAKE_WORLD_S", "30")
    t0 = time.monotonic()
    r = run.run_one(scenario, tmp_path / "b", 41000, timeout_s=0.5, system=s)
    assert r.world_sim_exit == 124 and time.monotonic() - t0 < 15
    assert "stopped after 0.5 s" in (tmp_path / "b/world_sim.log").read_text()


def test_an_unknown_absent_daemon_is_an_error(fake, tmp_path):
    s, scenario = fake
    with pytest.raises(KeyError, match="no daemon 'ghost'"):
        run.run_one(scenario, tmp_path / "o", 41000, absent=("ghost",), system=s)


def test_faults_orchestration_with_stand_ins(fake, tmp_path, monkeypatch, capsys):
    """faults: the clean, kill, absent and loss runs of one scenario with their arguments; the
    killed daemon is started again with its journal; the verdict table is written."""
    from coopnav_exp import cli
    monkeypatch.setenv("COOPNAV_FAULT_PORT_BASE", "41100")
    # The world runs long enough for the restarted stand-in to start (and log its command line)
    # on a loaded machine: the run stops as soon as the world exits.
    monkeypatch.setenv("FAKE_WORLD_S", "1.5")
    rc = cli.main(["faults", "--no-build", "--out", str(tmp_path / "f"), "--scenarios",
                   "narrow_minimal", "--kill", "band_source", "--seed", "3"])
    out = capsys.readouterr().out
    assert rc == 0, out
    lines = (tmp_path / "f/faults.txt").read_text().splitlines()
    assert [l.split()[1] for l in lines] == ["clean", "kill", "absent", "loss"]
    assert [l.split()[-1] for l in lines] == ["ok", "same", "same", "same"]
    assert "killed band_source (-9) at step" in out
    c = calls(tmp_path)
    bands = [x for x in c if x[0] == "coopnav_band_source"]
    kill_dir = str(tmp_path / "f/narrow_minimal/kill_band_source")
    killed = [x for x in bands if kill_dir + "/state" in x]
    assert len(killed) == 2, "started, killed, started again with its journal"
    assert "step_gate_timeout_s=60" in killed[1]
    # The kill run's scenario: the world waits longer, the map path absolute.
    scen = yaml.safe_load(Path(kill_dir, "scenario/narrow_minimal.yaml").read_text())
    assert scen["lockstep"]["step_timeout_s"] == 180
    assert Path(scen["map"]["file"]).is_absolute() and Path(scen["map"]["file"]).is_file()
    absent = [x for x in c if run.lcm_url(41120) in x]  # the third run's port
    assert not any(x[0] == "coopnav_obstacle_distance_server" for x in absent)
    assert any("distance_attempts=1" in x for x in absent if x[0] == "coopnav_situation_assessor")
    assert any(x[0] == "coopnav_lossy_relay" for x in c)
    ports = sorted({int(a.split(":")[2].split("?")[0]) for x in c for a in x[3:]
                    if isinstance(a, str) and a.startswith("udpm://")})
    assert ports[0] == 41100 and 41130 in ports  # ten ports a run, the fourth run's own


def test_scenario_sh_runs_one_run_with_the_scripts_hook(fake, tmp_path, monkeypatch, source_dir):
    """scripts/scenario.sh, the bash scripts' shell over run-one: its knobs from the
    environment, the hook while the world runs, world_sim's exit status returned."""
    import subprocess
    s, scenario = fake
    script = f'''
        source "{source_dir}/scripts/lib.sh"; source "{source_dir}/scripts/scenario.sh"
        coopnav_scenario_hook() {{ echo "hook $1 $LCM_DEFAULT_URL" >"{tmp_path}/hook"; }}
        echo "${{COOPNAV_DAEMONS[*]}}" >"{tmp_path}/daemons"
        rc=0; coopnav_run_scenario "{scenario}" "{tmp_path}/o" 41200 || rc=$?; echo "rc=$rc"'''
    env = dict(os.environ, COOPNAV_ABSENT="obstacle_distance_server", FAKE_WORLD_EXIT="5",
               COOPNAV_DAEMON_ARGS_world_sim="--set mode=real_time")
    p = subprocess.run(["bash", "-c", script], env=env, stdout=subprocess.PIPE, text=True,
                       timeout=60)
    assert p.stdout.strip() == "rc=5"
    assert (tmp_path / "hook").read_text() == f"hook scen {run.lcm_url(41200)}\n"
    assert (tmp_path / "daemons").read_text().split() == s.names()
    c = calls(tmp_path)
    assert not any(x[0] == "coopnav_obstacle_distance_server" for x in c)
    world = next(x for x in c if x[0] == "coopnav_world_sim")
    assert world[-4:-2] == ["--set", "mode=real_time"]
