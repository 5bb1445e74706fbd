"""The loop closed through DDS: narrow_minimal with the robot's ROS 2 side standing in for a real
robot. Two LCM buses: world_sim and coopnav_robot_side (test/dds/robot_side.cpp) on the "robot"
bus (the simulated base and its sensors), the daemons of config/system.yaml and
coopnav_ros2_bridge on the "pipeline" bus; between them only DDS: robot_side publishes /odom (odom
frame, origin at the robot's start pose, which the bridge is configured with), /tracked_agents and
/goal_pose from the world and applies /cmd_vel as the world's robot command. world_sim runs free
(real time) and gives no human goal (a robot's tracker knows none: the band source infers it).
What the simulated people perceive of the robot besides its body (its band, its words) robot_side
passes from the pipeline's bus to the world (--sim-cues-from): on a robot they see it and hear it.

Checks: the run reaches the decisions of the LCM-only run (the golden transcript of
narrow_minimal: what is said each round and the dock / resume); the utterances and the markers
arrive on the DDS side; then, in a second run, SIGKILL of band_source while the robot drives makes
the watchdog put zero on /cmd_vel within cmd_timeout_s (+ one watchdog period + slack).
All DDS on the loopback interface (test/dds/cyclonedds_loopback.xml) in domain 74. Skipped when
the bridge was not built (no Cyclone DDS). A third test runs the laser and /people the same way.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import time
from pathlib import Path

import pytest

from conftest import SOURCE_DIR
from coopnav_exp import run, supervise, system

BUILD_DIR = Path(os.environ.get("COOPNAV_BUILD_DIR") or SOURCE_DIR / "build")
BRIDGE = BUILD_DIR / "daemons/ros2_bridge/coopnav_ros2_bridge"
ROBOT_SIDE = BUILD_DIR / "test/coopnav_robot_side"
SCENARIO = SOURCE_DIR / "config/scenarios/narrow_minimal.yaml"
DOMAIN = 74
ODOM_ORIGIN = ("11.0", "1.575", "0.0")  # the robot's start pose in narrow_minimal: odom's origin
CMD_TIMEOUT_S = 0.5
WATCHDOG_SLACK_S = 0.05 + 0.25  # one watchdog period and scheduling


@pytest.fixture
def dds(tmp_path):
    if not (os.access(BRIDGE, os.X_OK) and os.access(ROBOT_SIDE, os.X_OK)):
        pytest.skip("coopnav_ros2_bridge / coopnav_robot_side not built (no Cyclone DDS)")
    base = int(os.environ.get("COOPNAV_TEST_PORT_BASE", "20000"))
    run.prepare(build=False)  # a multicast route and LCM's receive buffers
    env = dict(os.environ,
               CYCLONEDDS_URI=f"file://{SOURCE_DIR / 'test/dds/cyclonedds_loopback.xml'}")
    s = system.load()
    with supervise.Supervisor(grace_s=5.0) as sup:
        yield {"sup": sup, "env": env, "system": s, "tmp": tmp_path,
               "robot_bus": run.lcm_url(base), "pipe_bus": run.lcm_url(base + 1)}
        for p in sup.procs.values():  # shown when a test failed
            print(f"--- {p.log}\n" + "\n".join(p.log_tail(3)))


def start_pipeline(d: dict, scenario: Path = SCENARIO, bridge_args: tuple = ()) -> None:
    """system.yaml's daemons and the bridge on the pipeline bus, until each reports."""
    s, sup, tmp = d["system"], d["sup"], d["tmp"]
    for name in s.names():
        sup.start(name, s.command(name, scenario=scenario, lcm_url=d["pipe_bus"]),
                  tmp / f"{name}.log", env=d["env"])
    sup.start("ros2_bridge", [
        str(BRIDGE), "-c", str(s.config_dir / "ros2_bridge.yaml"), "--lcm-url", d["pipe_bus"],
        "--set", f"domain_id={DOMAIN}", "--set", f"odom_to_map_x_m={ODOM_ORIGIN[0]}",
        "--set", f"odom_to_map_y_m={ODOM_ORIGIN[1]}", "--set",
        f"odom_to_map_yaw_rad={ODOM_ORIGIN[2]}", "--set", f"cmd_timeout_s={CMD_TIMEOUT_S}",
        *bridge_args], tmp / "ros2_bridge.log",
        env=d["env"])
    names = s.names() + ["ros2_bridge"]
    sup.wait_ready([str(s.tool("ctl")), "--lcm-url", d["pipe_bus"], "wait-ready", *names,
                    "--timeout-s", "60"], names, env=d["env"])


def start_robot_side(d: dict, out: Path, extra: tuple = ()) -> None:
    d["sup"].start("robot_side", [
        str(ROBOT_SIDE), "--lcm-url", d["robot_bus"], "--domain", str(DOMAIN), "--odom-origin",
        *ODOM_ORIGIN, "--sim-cues-from", d["pipe_bus"], *extra], out, append=False, env=d["env"])
    time.sleep(1)  # DDS discovery between robot_side and the bridge (volatile topics)


def world_command(d: dict, scenario: Path = SCENARIO) -> list[str]:
    return d["system"].command("world_sim", scenario=scenario, lcm_url=d["robot_bus"], extra=[
        "--set", "mode=real_time", "--set", "publish_human_goals=false"])


def decisions(transcript: str) -> list[str]:
    """Each round's speech act and the robot's actions, in order."""
    return re.findall(r"SAY [A-Z_]+|ACTION [A-Z_]+", transcript)


def test_the_run_through_dds_makes_the_lcm_only_decisions(dds):
    d, tmp, s = dds, dds["tmp"], dds["system"]
    log = tmp / "pipeline.lcm"
    d["sup"].start("recorder", [str(s.tool("recorder")), "-f", "-c", s.recorder_channels,
                                "--lcm-url", d["pipe_bus"], str(log)], tmp / "record.log")
    start_pipeline(d)
    start_robot_side(d, tmp / "robot_side.out")
    world = d["sup"].start("world_sim", world_command(d), tmp / "world_sim.log", env=d["env"])
    try:
        rc = world.popen.wait(timeout=300)
    except subprocess.TimeoutExpired:
        rc = 124
    d["sup"].stop_all()
    print("\n".join(world.log_tail(2)))
    transcript = subprocess.run([str(s.tool("ctl")), "transcript", str(log), "--scenario",
                                 "narrow_minimal"], stdout=subprocess.PIPE, text=True).stdout
    robot_side = (tmp / "robot_side.out").read_text().splitlines()
    said_dds = [line[len("UTTERANCE "):] for line in robot_side if line.startswith("UTTERANCE ")]
    markers = [int(line.split()[1]) for line in robot_side if line.startswith("MARKERS ")]
    print("\n".join(line for line in transcript.splitlines()
                    if re.search(r"SAY|ACTION|SIM", line)))
    print(f"robot side: {sum(line.startswith('CMD ') for line in robot_side)} /cmd_vel, "
          f"{len(said_dds)} utterances, markers {markers}")
    assert rc == 0, f"world_sim exited {rc}"
    want = decisions((SOURCE_DIR / "test/data/golden/narrow_minimal.transcript").read_text())
    got = decisions(transcript)
    print(f"decisions LCM-only (golden): {want}\ndecisions through DDS:       {got}")
    assert got == want, "the decisions differ from the LCM-only run"
    # What was said reached the DDS side, word for word, in order.
    said_lcm = re.findall(r'SAY [A-Z_]+ "(.*)"', transcript)
    assert said_dds and said_dds == said_lcm, \
        f"the utterances on /coopnav/utterance are not those said: {said_dds} vs {said_lcm}"
    cp_h = [line for line in robot_side if line.startswith("MARKER cp_h 1")]
    assert markers and markers[-1] >= 10 and cp_h, \
        f"/coopnav/markers: {markers[-1] if markers else 0} arrays, CP_h of human 1 drawn " \
        f"{len(cp_h)} times"


def test_the_watchdog_zeroes_cmd_vel_when_band_source_dies(dds):
    d, tmp, sup = dds, dds["tmp"], dds["sup"]
    start_pipeline(d)
    out = tmp / "robot_side2.out"
    start_robot_side(d, out)
    world = sup.start("world_sim", world_command(d), tmp / "world_sim2.log", env=d["env"])

    def cmds() -> list[list[float]]:
        """/cmd_vel as robot_side printed it: [monotonic s, vx, vy, omega]."""
        return [[float(x) for x in line.split()[1:5]] for line in out.read_text().splitlines()
                if line.startswith("CMD ")]

    # Until the robot is commanded to move (a nonzero /cmd_vel), then 1 s more.
    for _ in range(100):
        if any(abs(c[1]) > 0.05 for c in cmds()):
            break
        time.sleep(0.1)
    time.sleep(1)
    sup.kill("band_source", signal.SIGKILL)
    time.sleep(CMD_TIMEOUT_S + 1.5)
    sup.stop([world])
    sup.stop_all()
    c = cmds()
    moving = [i for i, x in enumerate(c) if abs(x[1]) > 1e-9 or abs(x[3]) > 1e-9]
    assert moving, "the robot was never commanded to move"
    last = moving[-1]
    zeros = [x for x in c[last + 1:] if x[1:4] == [0.0, 0.0, 0.0]]
    assert zeros, f"no zero /cmd_vel after the last command ({len(c)} commands)"
    gap = zeros[0][0] - c[last][0]
    print(f"watchdog: zero on /cmd_vel {gap:.3f} s after the last command "
          f"(cmd_timeout_s {CMD_TIMEOUT_S})")
    assert gap <= CMD_TIMEOUT_S + WATCHDOG_SLACK_S, "the watchdog was late"
    assert "zero on /cmd_vel" in (tmp / "ros2_bridge.log").read_text(), \
        "the bridge did not log the watchdog"


def test_the_scan_and_people_go_through_dds(dds):
    """The laser and /people in closed loop: unmapped_box_encounter (a box the robot's map does
    not hold, and a person walking the way round it), the humans on /people (people_msgs/People,
    the bridge's humans_from: people) instead of /tracked_agents, the world's simulated laser on
    /scan (sensor_msgs/LaserScan, best effort). The scans robot_side wrote reach the pipeline's
    COOPNAV_SCAN unchanged (same stamp, rays and ranges), most of them; the person of /people is
    in the pipeline's agent states (id from the name); the robot, seeing the box only through the
    forwarded scan, touches neither the box nor the person and reaches its goal (the world's
    recorded run, summarized)."""
    from test_run_unmapped_box import unmapped_clearance_m

    d, tmp, s = dds, dds["tmp"], dds["system"]
    scenario = SOURCE_DIR / "test/data/scenarios/unmapped_box_encounter.yaml"
    log = tmp / "world.lcm"
    d["sup"].start("recorder", [str(s.tool("recorder")), "-f", "-c", s.recorder_channels,
                                "--lcm-url", d["robot_bus"], str(log)], tmp / "record.log")
    start_pipeline(d, scenario, ("--set", "humans_from=people"))
    out = tmp / "robot_side.out"
    start_robot_side(d, out, ("--people", "--echo-pipeline"))
    world = d["sup"].start("world_sim", world_command(d, scenario), tmp / "world_sim.log",
                           env=d["env"])
    try:
        rc = world.popen.wait(timeout=300)
    except subprocess.TimeoutExpired:
        rc = 124
    d["sup"].stop_all()
    assert rc == 0, f"world_sim exited {rc}"

    lines = [line.split() for line in out.read_text().splitlines()]
    written = {f[1]: f[2:5] for f in lines if f and f[0] == "SCAN"}
    forwarded = [f for f in lines if f and f[0] == "PIPE_SCAN"]
    differ = [f for f in forwarded if written.get(f[1]) != f[2:5]]
    print(f"scans: {len(written)} written on /scan, {len(forwarded)} on COOPNAV_SCAN, "
          f"{len(differ)} differ")
    assert len(written) >= 50, "too few scans written"
    assert len(forwarded) * 10 >= len(written) * 9, "most scans must reach COOPNAV_SCAN"
    assert not differ, f"forwarded scans differ from those written: {differ[:3]}"
    with_person = sum(1 for f in lines if f[:1] == ["PIPE_HUMANS"] and f[-1:] == ["1"])
    print(f"pipeline agent states with human 1 (from /people): {with_person}")
    assert with_person >= 20, "the person of /people is not in the pipeline's agent states"

    summary = tmp / "summary.json"
    subprocess.run([str(s.tool("ctl")), "summarize", str(log), "--scenario", scenario.stem,
                    "--out", str(summary)], check=True)
    from conftest import scenarios_of
    r = scenarios_of(summary)[scenario.stem]
    clearance = unmapped_clearance_m(scenario, tmp, log)
    print(f"{r['final_state']} at t = {r['sim_time_s']} s; clearance to the box {clearance:.3f} m")
    assert r["final_state"] == "GOAL_REACHED", r["detail"]
    assert not r["collision"] and r["contact"] is None, r["detail"]
    assert clearance > 0.0
