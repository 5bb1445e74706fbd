"""The system description (config/system.yaml): its daemons, their command lines, the profiles.

Every launcher builds its processes' command lines here and nowhere else. The bash scripts that
remain ask this command: `scripts/coopnav system daemons` (one name a line, in start order),
`scripts/coopnav system command NAME --scenario S` (the command line, one argument a line).
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import yaml

ROOT = Path(__file__).resolve().parents[3]
DEFAULT_PATH = ROOT / "config" / "system.yaml"
READY_KINDS = ("status",)


class SystemConfigError(ValueError):
    """A bad system.yaml: says which file and which key."""

    def __init__(self, path: Path, key: str, what: str):
        super().__init__(f"{path}: {key}: {what}")
        self.path, self.key, self.what = path, key, what


def build_dir() -> Path:
    """COOPNAV_BUILD_DIR, else build/ in the repository."""
    return Path(os.environ.get("COOPNAV_BUILD_DIR") or ROOT / "build").resolve()


@dataclass(frozen=True)
class Daemon:
    name: str
    binary: str  # relative to the build directory
    config: str  # relative to the config directory
    map_key: str | None = None
    holonomic_key: str | None = None
    journal: bool = False
    lockstep: bool = False
    ready: str = "status"
    replayed: bool = False


@dataclass(frozen=True)
class ProfileEntry:
    config: str | None = None
    args: tuple[str, ...] = ()


@dataclass(frozen=True)
class Variant:
    """A named way to run the same encounters (config/system.yaml `variants`, the ablation's):
    a profile, daemons left out (and out of the scenario's lockstep participants) and arguments
    added to a daemon's command line after the profile's."""

    name: str
    profile: str = "paper"
    absent: tuple[str, ...] = ()
    args: dict[str, tuple[str, ...]] = field(default_factory=dict)
    description: str = ""


@dataclass(frozen=True)
class Timing:
    ready_timeout_s: float = 60.0
    stop_grace_s: float = 10.0


@dataclass(frozen=True)
class System:
    path: Path
    config_dir: Path
    daemons: tuple[Daemon, ...]
    world: Daemon  # map_key unused; scenario_key below
    scenario_key: str
    recorder_binary: str
    recorder_channels: str
    tools: dict[str, str]
    timing: Timing
    profiles: dict[str, dict[str, ProfileEntry]] = field(default_factory=dict)
    variants: dict[str, Variant] = field(default_factory=dict)

    # ---- names ----
    def names(self) -> list[str]:
        return [d.name for d in self.daemons]

    def lockstep_names(self) -> list[str]:
        return [d.name for d in self.daemons if d.lockstep]

    def replayed_names(self) -> list[str]:
        return [d.name for d in self.daemons if d.replayed]

    def daemon(self, name: str) -> Daemon:
        for d in self.daemons:
            if d.name == name:
                return d
        if name == self.world.name:
            return self.world
        raise KeyError(f"no daemon '{name}' in {self.path} (daemons: {', '.join(self.names())}, "
                       f"world: {self.world.name})")

    # ---- paths ----
    def binary(self, name: str, build: Path | None = None) -> Path:
        return (build or build_dir()) / self.daemon(name).binary

    def tool(self, name: str, build: Path | None = None) -> Path:
        if name == "recorder":
            return (build or build_dir()) / self.recorder_binary
        return (build or build_dir()) / self.tools[name]

    # ---- command lines ----
    def command(self, name: str, *, scenario: Path | None, profile: str = "paper",
                state_dir: Path | None = None, extra: Sequence[str] = (),
                lcm_url: str | None = None, build: Path | None = None,
                config_dir: Path | None = None) -> list[str]:
        """The command line of daemon or world `name` in a run of `scenario` (None: no map or
        scenario argument; the config's own). config_dir: another folder of the same files."""
        if profile not in self.profiles:
            raise KeyError(f"no profile '{profile}' in {self.path} "
                           f"(profiles: {', '.join(self.profiles)})")
        d = self.daemon(name)
        entry = self.profiles[profile].get(name, ProfileEntry())
        cmd = [str(self.binary(name, build)), "-c",
               str((config_dir or self.config_dir) / (entry.config or d.config))]
        if scenario is not None and d is self.world:
            cmd += ["--set", f"{self.scenario_key}={scenario}"]
        elif scenario is not None and d.map_key:
            cmd += ["--set", f"{d.map_key}={scenario}"]
        if scenario is not None and d.holonomic_key:
            holonomic = scenario_kinematics(scenario) == "holonomic"
            cmd += ["--set", f"{d.holonomic_key}={'true' if holonomic else 'false'}"]
        cmd += list(entry.args)
        if state_dir is not None and d.journal:
            cmd += ["--state-dir", str(state_dir)]
        cmd += list(extra)
        if lcm_url:
            cmd += ["--lcm-url", lcm_url]
        return cmd


def one_of(names) -> str:
    """'a, b or c': the choices of an option, in a message."""
    names = list(names)
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " or " + names[-1]


def scenario_kinematics(scenario: Path) -> str:
    """The robot's kinematics a scenario declares (robot.kinematics; docs/scenario-format.md: the
    default is differential). An unreadable file gives the default: world_sim loads the file fully
    and reports its errors."""
    try:
        doc = yaml.safe_load(Path(scenario).read_text())
    except (OSError, yaml.YAMLError):
        return "differential"
    robot = doc.get("robot") if isinstance(doc, dict) else None
    kin = robot.get("kinematics") if isinstance(robot, dict) else None
    return kin if isinstance(kin, str) else "differential"


# ---- loading and validation ----

def _req(m: dict, key: str, where: str, path: Path, kind: type | tuple) -> Any:
    if not isinstance(m, dict) or key not in m:
        raise SystemConfigError(path, f"{where}.{key}" if where else key, "missing")
    v = m[key]
    if kind is float and isinstance(v, int) and not isinstance(v, bool):
        v = float(v)
    if not isinstance(v, kind) or (kind is not bool and isinstance(v, bool)):
        names = kind.__name__ if isinstance(kind, type) else "/".join(k.__name__ for k in kind)
        raise SystemConfigError(path, f"{where}.{key}" if where else key,
                                f"must be a {names}, not {v!r}")
    return v


def _opt(m: dict, key: str, where: str, path: Path, kind: type, default: Any) -> Any:
    return _req(m, key, where, path, kind) if key in m else default


def _no_other_keys(m: dict, allowed: set[str], where: str, path: Path) -> None:
    for k in m:
        if k not in allowed:
            raise SystemConfigError(path, f"{where}.{k}" if where else str(k),
                                    f"unknown key (allowed: {', '.join(sorted(allowed))})")


def _nonempty(s: str, key: str, path: Path) -> str:
    if not s.strip():
        raise SystemConfigError(path, key, "must not be empty")
    return s


def _daemon(m: Any, where: str, path: Path, config_dir: Path) -> Daemon:
    if not isinstance(m, dict):
        raise SystemConfigError(path, where, f"must be a mapping, not {m!r}")
    _no_other_keys(m, {"name", "binary", "config", "map_key", "holonomic_key", "journal",
                       "lockstep", "ready", "replayed"}, where, path)
    name = _nonempty(_req(m, "name", where, path, str), f"{where}.name", path)
    if not name.replace("_", "").isalnum():
        raise SystemConfigError(path, f"{where}.name", f"'{name}' is not a plain name")
    config = _nonempty(_req(m, "config", where, path, str), f"{where}.config", path)
    if not (config_dir / config).is_file():
        raise SystemConfigError(path, f"{where}.config", f"no file {config_dir / config}")
    ready = _opt(m, "ready", where, path, str, "status")
    if ready not in READY_KINDS:
        raise SystemConfigError(path, f"{where}.ready",
                                f"'{ready}' is not one of {', '.join(READY_KINDS)}")
    return Daemon(name=name,
                  binary=_nonempty(_req(m, "binary", where, path, str), f"{where}.binary", path),
                  config=config, map_key=_opt(m, "map_key", where, path, str, None),
                  holonomic_key=_opt(m, "holonomic_key", where, path, str, None),
                  journal=_opt(m, "journal", where, path, bool, False),
                  lockstep=_opt(m, "lockstep", where, path, bool, False), ready=ready,
                  replayed=_opt(m, "replayed", where, path, bool, False))


def load(path: Path | str | None = None) -> System:
    """Reads and checks system.yaml; raises SystemConfigError naming the file and the key."""
    path = Path(path or DEFAULT_PATH).resolve()
    try:
        text = path.read_text()
    except OSError as ex:
        raise SystemConfigError(path, "(file)", f"cannot read: {ex.strerror}") from ex
    try:
        doc = yaml.safe_load(text)
    except yaml.YAMLError as ex:
        raise SystemConfigError(path, "(file)", f"not YAML: {ex}") from ex
    if not isinstance(doc, dict):
        raise SystemConfigError(path, "(file)", "must be a mapping of daemons, world, recorder, "
                                                "tools, timing, profiles")
    _no_other_keys(doc, {"daemons", "world", "recorder", "tools", "timing", "profiles",
                         "variants"}, "", path)
    config_dir = path.parent
    raw = _req(doc, "daemons", "", path, list)
    if not raw:
        raise SystemConfigError(path, "daemons", "must list at least one daemon")
    daemons = tuple(_daemon(m, f"daemons[{i}]", path, config_dir) for i, m in enumerate(raw))
    seen: set[str] = set()
    for i, d in enumerate(daemons):
        if d.name in seen:
            raise SystemConfigError(path, f"daemons[{i}].name", f"'{d.name}' given twice")
        seen.add(d.name)

    w = _req(doc, "world", "", path, dict)
    world = _daemon({k: v for k, v in w.items() if k != "scenario_key"}, "world", path, config_dir)
    scenario_key = _nonempty(_req(w, "scenario_key", "world", path, str), "world.scenario_key",
                             path)
    if world.name in seen:
        raise SystemConfigError(path, "world.name", f"'{world.name}' is also a daemon")

    r = _req(doc, "recorder", "", path, dict)
    _no_other_keys(r, {"name", "binary", "channels"}, "recorder", path)
    rec_bin = _nonempty(_req(r, "binary", "recorder", path, str), "recorder.binary", path)
    rec_channels = _nonempty(_req(r, "channels", "recorder", path, str), "recorder.channels", path)

    t = _req(doc, "tools", "", path, dict)
    tools = {}
    for key in ("ctl", "lossy_relay", "viewer"):
        tools[key] = _nonempty(_req(t, key, "tools", path, str), f"tools.{key}", path)
    _no_other_keys(t, set(tools), "tools", path)

    tm = _opt(doc, "timing", "", path, dict, {})
    _no_other_keys(tm, set(Timing.__dataclass_fields__), "timing", path)
    values = {}
    for key, default in Timing().__dict__.items():
        v = _opt(tm, key, "timing", path, float, default)
        if not 0.0 <= v <= 3600.0:
            raise SystemConfigError(path, f"timing.{key}", f"{v} is outside [0, 3600] s")
        values[key] = v
    timing = Timing(**values)

    profiles: dict[str, dict[str, ProfileEntry]] = {}
    praw = _req(doc, "profiles", "", path, dict)
    if "paper" not in praw:
        raise SystemConfigError(path, "profiles.paper", "missing (the default profile)")
    for pname, entries in praw.items():
        where = f"profiles.{pname}"
        entries = entries or {}
        if not isinstance(entries, dict):
            raise SystemConfigError(path, where, f"must be a mapping of daemon names, not {entries!r}")
        profiles[str(pname)] = {}
        for dname, e in entries.items():
            ew = f"{where}.{dname}"
            if dname not in seen and dname != world.name:
                raise SystemConfigError(path, ew, f"no daemon '{dname}'")
            if not isinstance(e, dict):
                raise SystemConfigError(path, ew, f"must be a mapping (config, args), not {e!r}")
            _no_other_keys(e, {"config", "args"}, ew, path)
            cfg = _opt(e, "config", ew, path, str, None)
            if cfg is not None and not (config_dir / cfg).is_file():
                raise SystemConfigError(path, f"{ew}.config", f"no file {config_dir / cfg}")
            args = _opt(e, "args", ew, path, list, [])
            if not all(isinstance(a, str) for a in args):
                raise SystemConfigError(path, f"{ew}.args", "must be a list of strings")
            profiles[str(pname)][dname] = ProfileEntry(cfg, tuple(args))
    variants = _variants(_opt(doc, "variants", "", path, dict, {}), path, profiles, seen,
                         world.name)
    return System(path=path, config_dir=config_dir, daemons=daemons, world=world,
                  scenario_key=scenario_key, recorder_binary=rec_bin,
                  recorder_channels=rec_channels, tools=tools, timing=timing, profiles=profiles,
                  variants=variants)


def _variants(raw: dict, path: Path, profiles: dict, daemons: set[str],
              world: str) -> dict[str, Variant]:
    out: dict[str, Variant] = {}
    for vname, m in raw.items():
        where = f"variants.{vname}"
        if not isinstance(vname, str) or not vname.replace("_", "").isalnum():
            raise SystemConfigError(path, where, f"'{vname}' is not a plain name")
        m = m or {}
        if not isinstance(m, dict):
            raise SystemConfigError(path, where, f"must be a mapping, not {m!r}")
        _no_other_keys(m, {"profile", "absent", "args", "description"}, where, path)
        profile = _opt(m, "profile", where, path, str, "paper")
        if profile not in profiles:
            raise SystemConfigError(path, f"{where}.profile",
                                    f"no profile '{profile}' (profiles: {', '.join(profiles)})")
        absent = _opt(m, "absent", where, path, list, [])
        for i, d in enumerate(absent):
            if d not in daemons:
                raise SystemConfigError(path, f"{where}.absent[{i}]", f"no daemon '{d}'")
        args: dict[str, tuple[str, ...]] = {}
        for dname, a in (_opt(m, "args", where, path, dict, {}) or {}).items():
            aw = f"{where}.args.{dname}"
            if dname not in daemons and dname != world:
                raise SystemConfigError(path, aw, f"no daemon '{dname}'")
            if dname in absent:
                raise SystemConfigError(path, aw, f"'{dname}' is absent in this variant")
            if not isinstance(a, list) or not all(isinstance(x, str) for x in a):
                raise SystemConfigError(path, aw, "must be a list of strings")
            args[dname] = tuple(a)
        out[vname] = Variant(vname, profile, tuple(absent), args,
                             _opt(m, "description", where, path, str, ""))
    return out


# ---- command ----

def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--system", type=Path, default=None, help="system.yaml (default config/)")
    sub = p.add_subparsers(dest="what", required=True)
    d = sub.add_parser("daemons", help="the daemons' names in start order, one a line")
    d.add_argument("--lockstep", action="store_true", help="only the lockstep participants")
    d.add_argument("--replayed", action="store_true", help="only those a replay starts")
    d.add_argument("--with-world", action="store_true", help="and the world's name, last")
    c = sub.add_parser("command", help="a daemon's (or the world's) command line, one "
                                       "argument a line")
    c.add_argument("name")
    c.add_argument("--scenario", type=Path, default=None,
                   help="the run's scenario: the world's, and the map of the daemons that read one")
    c.add_argument("--profile", default="paper")
    c.add_argument("--state-dir", type=Path, default=None)
    c.add_argument("--lcm-url", default=None)
    c.add_argument("--config-dir", type=Path, default=None,
                   help="the config files from this folder (default config/)")
    b = sub.add_parser("binary", help="the path of a daemon's, the world's or a tool's executable")
    b.add_argument("name")
    sub.add_parser("check", help="load and check system.yaml; says what is wrong and where")


def main(args: argparse.Namespace) -> int:
    try:
        s = load(args.system)
        if args.what == "daemons":
            names = (s.lockstep_names() if args.lockstep else
                     s.replayed_names() if args.replayed else s.names())
            print("\n".join(names + ([s.world.name] if args.with_world else [])))
        elif args.what == "command":
            scen = args.scenario.absolute() if args.scenario else None
            print("\n".join(s.command(args.name, scenario=scen, profile=args.profile,
                                      state_dir=args.state_dir, lcm_url=args.lcm_url,
                                      config_dir=args.config_dir)))
        elif args.what == "binary":
            print(s.tool(args.name) if args.name in s.tools or args.name == "recorder"
                  else s.binary(args.name))
        elif args.what == "check":
            print(f"{s.path}: {len(s.daemons)} daemons, world {s.world.name}, profiles "
                  f"{', '.join(s.profiles)}")
    except (SystemConfigError, KeyError) as ex:
        print(f"coopnav system: {ex.args[0] if isinstance(ex, KeyError) else ex}", file=sys.stderr)
        return 2
    return 0
