"""config/system.yaml: the repository's file loads; each kind of mistake is refused with the
file and the key it is in; command lines are what the launchers ran before."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import yaml

from coopnav_exp import cli, system


@pytest.fixture
def sys_copy(tmp_path: Path, source_dir: Path) -> Path:
    """A copy of config/ (system.yaml names config files relative to its folder)."""
    cfg = tmp_path / "config"
    shutil.copytree(source_dir / "config", cfg, ignore=shutil.ignore_patterns("maps", "scenarios"))
    return cfg / "system.yaml"


def edit(path: Path, change) -> Path:
    doc = yaml.safe_load(path.read_text())
    change(doc)
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def test_the_repository_description_loads():
    s = system.load()
    assert s.names() == ["obstacle_distance_server", "band_source", "situation_assessor",
                         "path_assessor", "dialogue_manager"]
    assert s.lockstep_names() == ["band_source", "situation_assessor", "path_assessor",
                                  "dialogue_manager"]
    assert s.world.name == "world_sim"
    assert set(s.profiles) == {"paper", "calibrated", "forecast", "make_time"}


def test_every_paper_scenario_waits_for_exactly_the_lockstep_daemons(source_dir: Path):
    s = system.load()
    for f in sorted((source_dir / "config" / "scenarios").glob("*.yaml")):
        doc = yaml.safe_load(f.read_text())
        assert sorted(doc["lockstep"]["participants"]) == sorted(s.lockstep_names()), f.name


@pytest.mark.parametrize("change, key, what", [
    (lambda d: d.pop("daemons"), "daemons", "missing"),
    (lambda d: d.update(daemons=[]), "daemons", "at least one"),
    (lambda d: d["daemons"][1].pop("binary"), "daemons[1].binary", "missing"),
    (lambda d: d["daemons"][2].update(config="nope.yaml"), "daemons[2].config", "no file"),
    (lambda d: d["daemons"][0].update(journal="yes"), "daemons[0].journal", "must be a bool"),
    (lambda d: d["daemons"][0].update(ready="log line"), "daemons[0].ready", "not one of"),
    (lambda d: d["daemons"][0].update(colour="red"), "daemons[0].colour", "unknown key"),
    (lambda d: d["daemons"].append(dict(d["daemons"][0])), "daemons[5].name", "given twice"),
    (lambda d: d["world"].pop("scenario_key"), "world.scenario_key", "missing"),
    (lambda d: d["world"].update(name="band_source"), "world.name", "also a daemon"),
    (lambda d: d["recorder"].update(channels=""), "recorder.channels", "must not be empty"),
    (lambda d: d["tools"].pop("ctl"), "tools.ctl", "missing"),
    (lambda d: d["timing"].update(ready_timeout_s=-1), "timing.ready_timeout_s", "outside"),
    (lambda d: d["timing"].update(stop_grace_s="soon"), "timing.stop_grace_s", "must be a float"),
    (lambda d: d["profiles"].pop("paper"), "profiles.paper", "the default profile"),
    (lambda d: d["profiles"]["calibrated"].update(ghost={}), "profiles.calibrated.ghost",
     "no daemon 'ghost'"),
    (lambda d: d["profiles"]["calibrated"]["path_assessor"].update(config="x.yaml"),
     "profiles.calibrated.path_assessor.config", "no file"),
    (lambda d: d["profiles"]["paper"]["dialogue_manager"].update(args=[1]),
     "profiles.paper.dialogue_manager.args", "list of strings"),
])
def test_a_mistake_names_the_file_and_the_key(sys_copy: Path, change, key, what):
    edit(sys_copy, change)
    with pytest.raises(system.SystemConfigError) as ex:
        system.load(sys_copy)
    assert ex.value.key == key
    assert what in ex.value.what
    assert str(sys_copy) in str(ex.value)


def test_not_yaml_and_no_file(tmp_path: Path):
    bad = tmp_path / "system.yaml"
    bad.write_text("daemons: [\n")
    with pytest.raises(system.SystemConfigError, match="not YAML"):
        system.load(bad)
    with pytest.raises(system.SystemConfigError, match="cannot read"):
        system.load(tmp_path / "none.yaml")


def test_command_lines(tmp_path: Path):
    s = system.load()
    build = tmp_path / "b"
    cfg = s.config_dir
    scen = Path("/x/narrow_minimal.yaml")
    # The order scripts/scenario.sh gave: config, map, kinematics, profile, state, extra, URL.
    # A scenario that cannot be read declares no kinematics: the default, differential.
    assert s.command("band_source", scenario=scen, state_dir=Path("/st"),
                     extra=["--set", "a=1"], lcm_url="udpm://u", build=build) == [
        str(build / "daemons/band_source/coopnav_band_source"), "-c",
        str(cfg / "band_source.yaml"), "--set", f"map_file={scen}", "--set",
        "planner.robot.holonomic=false", "--state-dir", "/st", "--set", "a=1", "--lcm-url",
        "udpm://u"]
    # The band source plans for the robot the scenario declares.
    holo = tmp_path / "holo.yaml"
    holo.write_text("robot: {kinematics: holonomic}\n")
    assert "planner.robot.holonomic=true" in s.command("band_source", scenario=holo)
    # Stateless: no journal; the calibrated profile's config and the dialogue manager's profile.
    assert "--state-dir" not in s.command("obstacle_distance_server", scenario=scen,
                                          state_dir=Path("/st"))
    assert s.command("path_assessor", scenario=scen, profile="calibrated", build=build)[1:] == [
        "-c", str(cfg / "path_assessor_calibrated.yaml")]
    assert s.command("dialogue_manager", scenario=scen, profile="calibrated")[3:] == [
        "--set", "assessment_profile=calibrated"]
    assert s.command("world_sim", scenario=scen, build=build)[1:] == [
        "-c", str(cfg / "world_sim.yaml"), "--set", f"scenario={scen}"]
    with pytest.raises(KeyError, match="no profile 'bogus'"):
        s.command("band_source", scenario=scen, profile="bogus")
    with pytest.raises(KeyError, match="no daemon 'ghost'"):
        s.command("ghost", scenario=scen)


def test_the_system_command_answers_the_scripts(capsys):
    assert cli.main(["system", "daemons", "--with-world"]) == 0
    assert capsys.readouterr().out.split() == system.load().names() + ["world_sim"]
    assert cli.main(["system", "daemons", "--lockstep"]) == 0
    assert "obstacle_distance_server" not in capsys.readouterr().out
    assert cli.main(["system", "command", "ghost", "--scenario", "x.yaml"]) == 2
    assert "no daemon 'ghost'" in capsys.readouterr().err
