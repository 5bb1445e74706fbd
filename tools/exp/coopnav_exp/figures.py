"""Figures of recorded runs (paper Figs. 5-8), PNG and SVG, drawn with matplotlib.

`coopnav figures RUN_DIR... [--out DIR]`. A RUN_DIR is one scenario's run directory (its LCM log
`<name>.lcm`, `scenario.path` naming the scenario file, or a `trace.json` already written) or a
directory of such directories (`runs/latest`). Each run's data comes from `coopnav_ctl trace`
(`trace.json` in the run directory: states, path assessments, CA, utterances, actions, the band
source's modes, the map the scenario gives). Per run:

- `<name>_trajectories`: the robot's and each person's trajectory over the map's walls, time
  marks at the same instants on every track, CP_h / CP_r at the first round, where each utterance
  was decided (numbered, the words listed below the plot) and the dock (paper Figs. 5 and 6);
- `<name>_ca_cm`: CA over time (the whole interaction, window resets dashed) and CM over time
  (the window's and the interaction's) against τ, with the utterances, the dock and the band
  source's making-room modes marked (paper Fig. 8, and CM as the robot saw it);
- `<name>_cm_gamma`: CM against γ over the interaction's CA, with the γ and τ the run used
  (paper Fig. 7).

With several runs, also `trajectories`, `ca` and `cm_gamma` with every run (one panel per run for
the first two, one plot for Fig. 7) in --out (default: the runs' common parent directory); each
run's own figures go to --out when given, else to its run directory. Labels are placed where
their boxes (as matplotlib measures the text) overlap no other label and, when possible, no
track.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import string
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Sequence

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.text import Text
    from matplotlib.transforms import Bbox

ROOT = Path(__file__).resolve().parents[3]
ROBOT_COLOR = "#1f77b4"
HUMAN_COLORS = ["#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"]
WALL_COLOR = "#404040"
GUIDE_COLOR = "#7f7f7f"
MAKING_ROOM_MODES = {"docking": "#fdd0a2", "holding": "#fdae6b", "retreating": "#c6dbef",
                     "stopped": "#d9d9d9"}
FORMATS = ("png", "svg")
STILL_M = 0.1  # [m] a time mark this close to the agent's previous one is not labelled
MIN_WALL_M = 0.5  # [m] a wall outline smaller than this is not drawn as a line


def _pyplot() -> Any:
    """matplotlib's pyplot on the Agg backend, imported where a figure is drawn: importing it
    takes ~0.3 s, which every other command (and `scripts/coopnav --help`) need not pay."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _blend(x_transform: Any, y_transform: Any) -> Any:
    from matplotlib.transforms import blended_transform_factory

    return blended_transform_factory(x_transform, y_transform)


class TraceError(Exception):
    """A run directory without a log or a trace, or a trace that is not coopnav_ctl's."""


# ---------------------------------------------------------------------------------------------
# Reading a trace


def _arr(values: Iterable[Any]) -> np.ndarray:
    """JSON numbers (null for NaN) as a float array."""
    return np.array([np.nan if v is None else float(v) for v in values], dtype=float)


@dataclass
class Track:
    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    radius_m: float

    def at(self, t_s: float) -> tuple[float, float]:
        """Position at t_s (the last state at or before it; the first when t_s is earlier)."""
        if len(self.t) == 0:
            return (math.nan, math.nan)
        k = max(0, int(np.searchsorted(self.t, t_s, side="right")) - 1)
        return (float(self.x[k]), float(self.y[k]))


def _track(m: dict) -> Track:
    r = m.get("radius_m")
    return Track(_arr(m["t_s"]), _arr(m["x_m"]), _arr(m["y_m"]),
                 math.nan if r is None else float(r))


@dataclass
class Trace:
    name: str
    doc: dict
    robot: Track
    humans: dict[int, Track] = field(default_factory=dict)

    @property
    def assessments(self) -> list[dict]:
        return self.doc.get("assessments") or []

    @property
    def utterances(self) -> list[dict]:
        return self.doc.get("utterances") or []

    @property
    def actions(self) -> list[dict]:
        return self.doc.get("actions") or []

    @property
    def modes(self) -> list[dict]:
        return self.doc.get("modes") or []

    @property
    def map(self) -> dict | None:
        return self.doc.get("map")

    def end_s(self) -> float:
        ts = [self.robot.t[-1]] if len(self.robot.t) else []
        ts += [h.t[-1] for h in self.humans.values() if len(h.t)]
        return float(max(ts)) if ts else 0.0

    def start_s(self) -> float:
        return float(self.robot.t[0]) if len(self.robot.t) else 0.0


def trace_from_doc(doc: dict, name: str | None = None) -> Trace:
    if doc.get("format") != "coopnav-trace":
        raise TraceError("not a coopnav_ctl trace (no \"format\": \"coopnav-trace\")")
    humans = {int(h["id"]): _track(h) for h in doc.get("humans") or []}
    return Trace(name or doc.get("scenario") or "run", doc, _track(doc["robot"]), humans)


def read_trace(path: Path) -> Trace:
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as e:
        raise TraceError(f"{path}: {e}") from e
    return trace_from_doc(doc)


def ctl_path() -> Path:
    """coopnav_ctl of COOPNAV_BUILD_DIR (default build/ in the repository)."""
    build = Path(os.environ.get("COOPNAV_BUILD_DIR") or ROOT / "build")
    return build.resolve() / "tools" / "coopnav_ctl"


def _log_of(run_dir: Path) -> Path | None:
    own = run_dir / f"{run_dir.name}.lcm"
    if own.is_file():
        return own
    logs = sorted(run_dir.glob("*.lcm"))
    return logs[0] if len(logs) == 1 else None


def is_run_dir(d: Path) -> bool:
    return d.is_dir() and ((d / "trace.json").is_file() or _log_of(d) is not None)


def trace_of_run(run_dir: Path, ctl: Path | None = None) -> Trace:
    """The run's trace: trace.json, written by `coopnav_ctl trace` when missing or older than
    the log (with the map of the scenario file named in scenario.path, when there is one)."""
    out = run_dir / "trace.json"
    log = _log_of(run_dir)
    if log is not None and (not out.is_file() or out.stat().st_mtime < log.stat().st_mtime):
        cmd = [str(ctl or ctl_path()), "trace", str(log), "--json", str(out)]
        scenario = run_dir / "scenario.path"
        if scenario.is_file():
            cmd += ["--map", scenario.read_text(encoding="utf-8").strip()]
        r = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if r.returncode != 0:
            raise TraceError(f"{' '.join(cmd)}: exit {r.returncode}: {r.stderr.strip()}")
    if not out.is_file():
        raise TraceError(f"{run_dir}: no LCM log and no trace.json")
    return read_trace(out)


def find_runs(dirs: Sequence[Path]) -> list[Path]:
    """Each given run directory, or the run directories inside a given directory (sorted)."""
    runs: list[Path] = []
    for d in dirs:
        if is_run_dir(d):
            runs.append(d)
            continue
        inner = sorted(c for c in d.iterdir() if is_run_dir(c)) if d.is_dir() else []
        if not inner:
            raise TraceError(f"{d}: not a run directory (no LCM log or trace.json) and holds none")
        runs.extend(inner)
    return runs


# ---------------------------------------------------------------------------------------------
# Label placement


class LabelPlacer:
    """Places text labels of one axes so that no two boxes overlap.

    Candidates around the anchor point are tried nearest first; a candidate is taken when its
    box (matplotlib's window extent of the text, padded) lies inside the axes, overlaps no label
    placed before and covers no point to avoid (track samples, markers). When every candidate
    covers such a point, the first that overlaps no label is taken; when even that fails the
    label is left out (returned None) rather than drawn over another.
    """

    def __init__(self, ax: Axes, pad_px: float = 2.0):
        self.ax = ax
        self.pad = pad_px
        ax.figure.canvas.draw()  # fixes the layout: boxes are measured in their final place
        self.renderer = ax.figure.canvas.get_renderer()
        self.boxes: list[Bbox] = []
        self.points = np.empty((0, 2))

    def avoid_data(self, x: np.ndarray, y: np.ndarray) -> None:
        pts = np.column_stack([np.asarray(x, float), np.asarray(y, float)])
        pts = pts[np.isfinite(pts).all(axis=1)]
        if len(pts):
            self.points = np.vstack([self.points, self.ax.transData.transform(pts)])

    def avoid_box(self, box: Bbox) -> None:
        self.boxes.append(box)

    def _box(self, t: Text) -> Bbox:
        return t.get_window_extent(self.renderer).padded(self.pad)

    def _covers_points(self, b: Bbox) -> bool:
        if not len(self.points):
            return False
        p = self.points
        return bool(np.any((p[:, 0] >= b.x0) & (p[:, 0] <= b.x1) & (p[:, 1] >= b.y0)
                           & (p[:, 1] <= b.y1)))

    @staticmethod
    def _offsets(base: float) -> list[tuple[float, float]]:
        out = []
        for r in (1.0, 2.0, 3.5, 5.0, 7.0):
            d = base * r
            out += [(d, d), (d, -d), (-d, d), (-d, -d), (0, 1.4 * d), (0, -1.4 * d),
                    (1.4 * d, 0), (-1.4 * d, 0)]
        return out

    def place(self, text: str, x: float, y: float, *, offset_pt: float = 5.0,
              transform: Any = None, **kw: Any) -> Text | None:
        if not (math.isfinite(x) and math.isfinite(y)):
            return None
        axes_box = self.ax.get_window_extent(self.renderer)
        t = self.ax.annotate(text, (x, y), xycoords=transform or "data", xytext=(0, 0),
                             textcoords="offset points", annotation_clip=False, **kw)
        fallback = None
        for dx, dy in self._offsets(offset_pt):
            self._move(t, dx, dy)
            b = self._box(t)
            inside = (b.x0 >= axes_box.x0 and b.x1 <= axes_box.x1 and b.y0 >= axes_box.y0
                      and b.y1 <= axes_box.y1)
            free = inside and not any(b.overlaps(o) for o in self.boxes)
            if free and not self._covers_points(b):
                self.boxes.append(b)
                return t
            if free and fallback is None:
                fallback = (dx, dy)
        if fallback is None:
            t.remove()
            return None
        self._move(t, *fallback)
        self.boxes.append(self._box(t))
        return t

    @staticmethod
    def _move(t: Text, dx: float, dy: float) -> None:
        t.xyann = (dx, dy)
        t.set_horizontalalignment("left" if dx > 0 else "right" if dx < 0 else "center")
        t.set_verticalalignment("bottom" if dy > 0 else "top" if dy < 0 else "center")


def label_boxes_overlap(fig: Figure) -> list[tuple[str, str]]:
    """Pairs of texts of each axes (labels, legend entries) whose drawn boxes overlap."""
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    pairs = []
    for ax in fig.axes:
        texts = [t for t in ax.texts if t.get_visible() and t.get_text()]
        legend = ax.get_legend()
        if legend is not None:
            texts += [t for t in legend.get_texts() if t.get_text()]
        boxes = [t.get_window_extent(r) for t in texts]
        for i in range(len(texts)):
            for j in range(i + 1, len(texts)):
                if boxes[i].overlaps(boxes[j]):
                    pairs.append((texts[i].get_text(), texts[j].get_text()))
    return pairs


# ---------------------------------------------------------------------------------------------
# Drawing


def _human_color(k: int) -> str:
    return HUMAN_COLORS[k % len(HUMAN_COLORS)]


def _nice_step(span: float, target: int) -> float:
    for step in (0.5, 1, 2, 5, 10, 20, 30, 60, 120):
        if span / step <= target:
            return float(step)
    return 300.0


def _view(trace: Trace, margin_m: float = 1.2) -> tuple[float, float, float, float]:
    xs = [trace.robot.x] + [h.x for h in trace.humans.values()]
    ys = [trace.robot.y] + [h.y for h in trace.humans.values()]
    x = np.concatenate(xs) if xs else np.array([0.0])
    y = np.concatenate(ys) if ys else np.array([0.0])
    x, y = x[np.isfinite(x)], y[np.isfinite(y)]
    if not len(x):
        return (-1.0, 1.0, -1.0, 1.0)
    x0, x1, y0, y1 = x.min(), x.max(), y.min(), y.max()
    tracks_y = (y0, y1)
    m = trace.map
    if m and m.get("walls"):
        # A synthetic corridor: show its walls whole across the tracks' span.
        for w in m["walls"]:
            if None in w:
                continue
            wx0, wy0, wx1, wy1 = w
            if max(wx0, wx1) >= x0 - margin_m and min(wx0, wx1) <= x1 + margin_m:
                y0, y1 = min(y0, wy0, wy1), max(y1, wy0, wy1)
    elif m:
        grid = obstacle_grid(m)
        if grid is not None:
            y0, y1 = _walls_beside(grid, x0, x1, y0, y1)
    # Beyond a wall little is worth showing; beyond a track without a wall, its surroundings.
    below = 0.4 if y0 < tracks_y[0] else margin_m
    above = 0.4 if y1 > tracks_y[1] else margin_m
    return (x0 - margin_m, x1 + margin_m, y0 - below, y1 + above)


def _walls_beside(grid: tuple[np.ndarray, float, float, float], x0: float, x1: float,
                  y0: float, y1: float, reach_m: float = 4.0) -> tuple[float, float]:
    """y0, y1 widened to the nearest wall below and above the tracks (a row of the grid that
    is obstacle over most of the tracks' x span), at most reach_m away: a corridor shows whole."""
    occ, res, ox, oy = grid
    i0 = max(0, int((x0 - ox) / res))
    i1 = min(occ.shape[1], int((x1 - ox) / res) + 1)
    if i1 <= i0:
        return y0, y1
    walls = occ[:, i0:i1].mean(axis=1) > 0.5
    reach = int(reach_m / res)
    j0, j1 = int((y0 - oy) / res), int((y1 - oy) / res)
    for j in range(j0, max(j0 - reach, -1), -1):
        if 0 <= j < occ.shape[0] and walls[j]:
            y0 = min(y0, oy + j * res)
            break
    for j in range(j1, min(j1 + reach, occ.shape[0])):
        if j >= 0 and walls[j]:
            y1 = max(y1, oy + (j + 1) * res)
            break
    return y0, y1


def obstacle_grid(m: dict) -> tuple[np.ndarray, float, float, float] | None:
    """The map's obstacle cells as a bool array [row j (y up), column i], with resolution and
    origin; None when the trace has no grid."""
    w, h, res = m.get("width"), m.get("height"), m.get("resolution_m")
    if not w or not h or not res:
        return None
    occ = np.zeros((int(h), int(w)), dtype=bool)
    for j, i0, i1 in m.get("obstacle_runs") or []:
        occ[int(j), int(i0):int(i1)] = True
    ox, oy = m.get("origin_m") or (0.0, 0.0)
    return occ, float(res), float(ox), float(oy)


def _is_wall_outline(v: np.ndarray) -> bool:
    """A contour of the obstacle grid worth a line: not a speck (under MIN_WALL_M each way) and
    not a small closed pocket (a free hole inside a wall, under MIN_WALL_M² of area)."""
    if len(v) < 2 or np.ptp(v, axis=0).max() < MIN_WALL_M:
        return False
    if np.allclose(v[0], v[-1]):
        area = 0.5 * abs(np.dot(v[:, 0], np.roll(v[:, 1], 1)) - np.dot(v[:, 1], np.roll(v[:, 0], 1)))
        return area >= MIN_WALL_M ** 2
    return True


def draw_map(ax: Axes, m: dict | None, view: tuple[float, float, float, float]) -> int:
    """Walls and boxes of the map within view; returns the number of wall artists drawn."""
    if not m:
        return 0
    x0, x1, y0, y1 = view
    drawn = 0
    grid = obstacle_grid(m)
    has_segments = bool(m.get("walls")) or bool(m.get("boxes"))
    if grid is not None:
        occ, res, ox, oy = grid
        i0 = max(0, int(math.floor((x0 - ox) / res)))
        i1 = min(occ.shape[1], int(math.ceil((x1 - ox) / res)))
        j0 = max(0, int(math.floor((y0 - oy) / res)))
        j1 = min(occ.shape[0], int(math.ceil((y1 - oy) / res)))
        if i1 > i0 and j1 > j0:
            crop = occ[j0:j1, i0:i1]
            extent = (ox + i0 * res, ox + i1 * res, oy + j0 * res, oy + j1 * res)
            img = ax.imshow(np.where(crop, 1.0, np.nan), origin="lower", extent=extent,
                            cmap="Greys", vmin=0.0, vmax=2.5, interpolation="nearest", zorder=0)
            img.set_gid("walls-fill")
            if not has_segments and crop.any() and not crop.all():
                xs = ox + (np.arange(i0, i1) + 0.5) * res
                ys = oy + (np.arange(j0, j1) + 0.5) * res
                cs = ax.contour(xs, ys, crop.astype(float), levels=[0.5], colors=WALL_COLOR,
                                linewidths=1.2, zorder=1)
                for c in cs.collections:
                    # Specks (a free pocket inside a wall, a scanned map's noise) are no walls.
                    c.set_paths([p for p in c.get_paths() if _is_wall_outline(p.vertices)])
                    c.set_gid("walls")
                    drawn += 1
    for w in m.get("walls") or []:
        if None in w:
            continue
        (line,) = ax.plot([w[0], w[2]], [w[1], w[3]], color=WALL_COLOR, lw=2.0, zorder=1,
                          solid_capstyle="butt")
        line.set_gid("walls")
        drawn += 1
    for b in m.get("boxes") or []:
        if None in b:
            continue
        rect = _pyplot().Rectangle((b[0], b[1]), b[2] - b[0], b[3] - b[1], facecolor="#bdbdbd",
                             edgecolor=WALL_COLOR, lw=1.2, zorder=1)
        rect.set_gid("walls")
        ax.add_patch(rect)
        drawn += 1
    return drawn


def _map_name(m: dict | None) -> str:
    if not m:
        return "no map given"
    return "map " + Path(m.get("file") or m.get("path") or "?").name


def _first_time(trace: Trace, modes: set[str]) -> float | None:
    for e in trace.modes:
        if e.get("mode") in modes and e.get("t_s") is not None:
            return float(e["t_s"])
    return None


def draw_trajectories(ax: Axes, trace: Trace, *, mark_step_s: float | None = None,
                      legend: bool = True) -> None:
    """Fig. 5 / 6 panel: tracks over the walls, time marks, CP_h / CP_r, utterances, dock."""
    view = _view(trace)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlim(view[0], view[1])
    ax.set_ylim(view[2], view[3])
    draw_map(ax, trace.map, view)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{trace.name}: trajectories ({_map_name(trace.map)})", fontsize=10)

    tracks = [("robot", ROBOT_COLOR, trace.robot)]
    tracks += [(f"human {i}", _human_color(k), tr)
               for k, (i, tr) in enumerate(sorted(trace.humans.items()))]
    for label, color, tr in tracks:
        ax.plot(tr.x, tr.y, color=color, lw=2.0 if label == "robot" else 1.6, label=label,
                zorder=3)
    t0, t1 = trace.start_s(), trace.end_s()
    step = mark_step_s or _nice_step(max(t1 - t0, 1e-9), 10)
    marks = np.arange(math.ceil(t0 / step) * step, t1 + 1e-9, step)
    for _, color, tr in tracks:
        pts = np.array([tr.at(t) for t in marks]) if len(marks) else np.empty((0, 2))
        if len(pts):
            ax.scatter(pts[:, 0], pts[:, 1], s=14, color=color, edgecolors="black",
                       linewidths=0.4, zorder=4)

    # Crossing points at the first round.
    cps = []
    for k, a in enumerate(trace.assessments):
        fr = a.get("first_round")
        if not fr:
            continue
        for key, color, marker, name in (("cp_h_m", _human_color(k), "o", "CP_h"),
                                         ("cp_r_m", ROBOT_COLOR, "s", "CP_r")):
            p = fr.get(key) or [None, None]
            if None in p:
                continue
            ax.scatter([p[0]], [p[1]], s=46, marker=marker, facecolor="white", edgecolor=color,
                       linewidths=1.6, zorder=5)
            label = name if len(trace.assessments) == 1 else f"{name} {a['id']}"
            cps.append((label, p[0], p[1], color))

    # Where each utterance was decided (the robot's position then) and the dock.
    said_points = []
    for n, u in enumerate(trace.utterances, start=1):
        if u.get("t_s") is not None:
            x, y = trace.robot.at(float(u["t_s"]))
            said_points.append((str(n), x, y))
    docks = []
    for a in trace.actions:
        if a.get("action") == "DOCK" and a.get("t_s") is not None:
            x, y = trace.robot.at(float(a["t_s"]))
            docks.append((f"dock decided {float(a['t_s']):.1f} s", x, y))
    t_hold = _first_time(trace, {"holding"})
    if t_hold is not None:
        x, y = trace.robot.at(t_hold)
        docks.append((f"at the dock {t_hold:.1f} s", x, y))
    for _, x, y in said_points:
        ax.scatter([x], [y], s=60, marker="o", facecolor="#ffffcc", edgecolor="black",
                   linewidths=0.8, zorder=6)
    for _, x, y in docks:
        ax.scatter([x], [y], s=70, marker="D", facecolor="#fd8d3c", edgecolor="black",
                   linewidths=0.8, zorder=6)

    if legend:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    placer = LabelPlacer(ax)
    for _, _, tr in tracks:
        placer.avoid_data(tr.x, tr.y)
    # Most important first: they get the nearest places.
    for label, x, y in docks:
        placer.place(label, x, y, fontsize=7.5, color="#a63603")
    for label, x, y in said_points:
        placer.place(label, x, y, fontsize=8, fontweight="bold",
                     bbox=dict(boxstyle="circle,pad=0.15", fc="#ffffcc", ec="black", lw=0.6))
    for label, x, y, color in cps:
        placer.place(label, x, y, fontsize=7.5, color=color)
    for _, color, tr in tracks:
        last = (math.inf, math.inf)
        for t in marks:
            x, y = tr.at(t)
            if math.hypot(x - last[0], y - last[1]) < STILL_M:
                continue  # standing still: the earlier mark says since when
            last = (x, y)
            placer.place(f"{t:g} s", x, y, offset_pt=3.0, fontsize=6.5, color=color)


def _caption_text(lines: list[str]) -> str:
    return "\n".join(lines) if lines else "(nothing said)"


def trajectories_figure(trace: Trace) -> Figure:
    lines = _utterance_caption_lines(trace)
    x0, x1, y0, y1 = _view(trace)
    aspect = (y1 - y0) / max(x1 - x0, 1e-9)
    width = 11.0
    plot_h = min(max(width * 0.78 * aspect, 1.6), 7.0)
    cap_h = 0.18 * (len(lines) + 1)
    fig = _pyplot().figure(figsize=(width, plot_h + 1.0 + cap_h))
    bottom = (0.55 + cap_h) / fig.get_figheight()
    ax = fig.add_axes([0.07, bottom, 0.78, 1.0 - bottom - 0.35 / fig.get_figheight()])
    draw_trajectories(ax, trace)
    # The words right under the axes (as drawn, with their equal aspect): saved tight.
    box = ax.get_tightbbox(fig.canvas.get_renderer()).transformed(fig.transFigure.inverted())
    fig.text(box.x0, box.y0 - 0.08 / fig.get_figheight(), _caption_text(lines), fontsize=7.5,
             va="top", ha="left")
    return fig


def _utterance_caption_lines(trace: Trace) -> list[str]:
    lines = []
    for n, u in enumerate(trace.utterances, start=1):
        if u.get("t_s") is None:
            continue
        words = u.get("text") or ""
        if len(words) > 90:
            words = words[:87] + "..."
        state = "" if u.get("said", True) else f" [not said: {u.get('delivery')}]"
        lines.append(f"{n}: t={float(u['t_s']):.1f} s, human {u.get('human_id')}, round "
                     f"{u.get('round')}, {u.get('act')}{state}: \"{words}\"")
    return lines


def _shade_modes(ax: Axes, trace: Trace, t_end: float, seen: set[str]) -> None:
    modes = [(float(e["t_s"]), e.get("mode")) for e in trace.modes if e.get("t_s") is not None]
    for k, (t, mode) in enumerate(modes):
        if mode not in MAKING_ROOM_MODES:
            continue
        t_next = modes[k + 1][0] if k + 1 < len(modes) else t_end
        label = f"robot {mode}" if mode not in seen else None
        seen.add(mode)
        ax.axvspan(t, t_next, color=MAKING_ROOM_MODES[mode], alpha=0.6, lw=0, zorder=0,
                   label=label)


def draw_ca(ax: Axes, trace: Trace, *, title: bool = True) -> None:
    """CA over time per human (Fig. 8 panel)."""
    ax.axhline(0.0, color=GUIDE_COLOR, lw=0.8, zorder=1)
    for k, a in enumerate(trace.assessments):
        ca = a.get("ca") or {}
        t, v = _arr(ca.get("t_s") or []), _arr(ca.get("ca_m") or [])
        if not len(v):
            continue
        whole = ca.get("whole_interaction", False)
        ax.plot(t, v, color=_human_color(k), lw=1.6, zorder=3,
                label=f"human {a['id']}" + ("" if whole else " (last window)"))
        for ts in ca.get("window_start_t_s") or []:
            if ts is not None and len(t) and ts > t[0]:
                ax.axvline(ts, color=_human_color(k), ls="--", lw=0.9, zorder=2)
    ax.set_ylabel("CA [m] (> 0: away from the robot)")
    if title:
        ax.set_title(f"{trace.name}: CA over time", fontsize=10)


def _tau_of(a: dict) -> float:
    taus = [v for v in _arr(a.get("tau_m") or []) if math.isfinite(v)]
    if taus:
        return float(taus[-1])
    t = a.get("tau_fixed_m")
    return math.nan if t is None else float(t)


def ca_cm_figure(trace: Trace) -> Figure:
    fig, (ax_ca, ax_cm) = _pyplot().subplots(2, 1, sharex=True, figsize=(10.5, 6.2))
    fig.subplots_adjust(left=0.09, right=0.76, top=0.93, bottom=0.09, hspace=0.12)
    draw_ca(ax_ca, trace, title=False)
    fig.suptitle(f"{trace.name}: CA and CM over time", fontsize=11)
    for k, a in enumerate(trace.assessments):
        t = _arr(a.get("t_s") or [])
        if not len(t):
            continue
        color = _human_color(k)
        ax_cm.plot(t, _arr(a.get("cm_m") or []), color=color, lw=1.6, zorder=3,
                   label=f"human {a['id']}: CM (window)")
        ax_cm.plot(t, _arr(a.get("cm_interaction_m") or []), color=color, lw=1.2, ls="--",
                   zorder=3, label=f"human {a['id']}: CM (interaction)")
        ax_cm.step(t, _arr(a.get("tau_m") or []), where="post", color=GUIDE_COLOR, lw=1.0,
                   ls=":", zorder=2, label="τ in force" if k == 0 else None)
    ax_cm.set_ylabel("CM [m]")
    ax_cm.set_xlabel("simulated time [s]")
    t_end = trace.end_s()
    seen: set[str] = set()
    for ax in (ax_ca, ax_cm):
        _shade_modes(ax, trace, t_end, seen if ax is ax_ca else set(seen))
    events = [(float(u["t_s"]), str(n)) for n, u in enumerate(trace.utterances, start=1)
              if u.get("t_s") is not None]
    docks = [(float(a["t_s"]), "dock") for a in trace.actions
             if a.get("action") == "DOCK" and a.get("t_s") is not None]
    for t, _ in events:
        for ax in (ax_ca, ax_cm):
            ax.axvline(t, color="black", lw=0.7, alpha=0.55, zorder=1)
    for t, _ in docks:
        for ax in (ax_ca, ax_cm):
            ax.axvline(t, color="#e6550d", lw=1.4, zorder=1)
    if trace.start_s() < t_end:
        ax_cm.set_xlim(trace.start_s(), t_end)
    for ax in (ax_ca, ax_cm):
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    # Event labels along the top of the CA axes (x in data, y in axes fraction).
    placer = LabelPlacer(ax_ca)
    blend = _blend(ax_ca.transData, ax_ca.transAxes)
    for t, label in docks + events:
        bbox = None if label == "dock" else dict(boxstyle="circle,pad=0.15", fc="#ffffcc",
                                                   ec="black", lw=0.6)
        placer.place(label, t, 0.97, transform=blend, offset_pt=2.0, fontsize=7.5, bbox=bbox,
                     color="#a63603" if label == "dock" else "black")
    lines = _utterance_caption_lines(trace)
    if lines:
        fig.set_figheight(fig.get_figheight() + 0.17 * len(lines))
        fig.subplots_adjust(bottom=(0.5 + 0.17 * len(lines)) / fig.get_figheight())
        fig.text(0.09, 0.08 / fig.get_figheight(), _caption_text(lines), fontsize=7.5,
                 va="bottom")
    return fig


def draw_cm_gamma(ax: Axes, traces: Sequence[Trace]) -> None:
    """Fig. 7: CM against γ over each human's interaction CA, γ and τ of the runs marked."""
    gammas, taus, profiles = set(), set(), set()
    k = 0
    for tr in traces:
        for a in tr.assessments:
            cg = a.get("cm_by_gamma") or {}
            g, cm = _arr(cg.get("gamma") or []), _arr(cg.get("cm_m") or [])
            if len(cm) and np.isfinite(cm).any():
                label = tr.name if len(tr.assessments) == 1 else f"{tr.name} human {a['id']}"
                ax.plot(g, cm, color=_human_color(k), lw=1.6, label=label, zorder=3)
                k += 1
            if a.get("gamma") is not None:
                gammas.add(round(float(a["gamma"]), 4))
            tau = _tau_of(a)
            if math.isfinite(tau):
                taus.add(round(tau, 4))
            if a.get("profile"):
                profiles.add(str(a["profile"]))
    placer_items = []
    for g in sorted(gammas):
        ax.axvline(g, color=GUIDE_COLOR, ls="--", lw=1.0, zorder=2)
        placer_items.append((f"γ = {g:g}", g, "v"))
    for tau in sorted(taus):
        ax.axhline(tau, color=GUIDE_COLOR, ls=":", lw=1.0, zorder=2)
        placer_items.append((f"τ = {tau:.2f} m", tau, "h"))
    ax.set_xlabel("γ")
    ax.set_ylabel("CM [m]")
    prof = ", ".join(sorted(profiles)) or "-"
    ax.set_title(f"CM as a function of γ (profile {prof})", fontsize=10)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    placer = LabelPlacer(ax)
    for line in ax.get_lines():
        if line.get_label() and not line.get_label().startswith("_"):
            placer.avoid_data(line.get_xdata(), line.get_ydata())
    xform_v = _blend(ax.transData, ax.transAxes)
    xform_h = _blend(ax.transAxes, ax.transData)
    for label, v, kind in placer_items:
        if kind == "v":
            placer.place(label, v, 0.03, transform=xform_v, offset_pt=3.0, fontsize=8,
                         color="#525252")
        else:
            placer.place(label, 0.02, v, transform=xform_h, offset_pt=3.0, fontsize=8,
                         color="#525252")


def cm_gamma_figure(traces: Sequence[Trace]) -> Figure:
    fig = _pyplot().figure(figsize=(9.0, 4.6))
    ax = fig.add_axes([0.09, 0.12, 0.62, 0.8])
    draw_cm_gamma(ax, traces)
    return fig


def trajectories_panels(traces: Sequence[Trace]) -> Figure:
    heights = []
    for tr in traces:
        x0, x1, y0, y1 = _view(tr)
        heights.append(min(max(11.0 * 0.78 * (y1 - y0) / max(x1 - x0, 1e-9), 1.6), 5.0) + 0.8)
    fig = _pyplot().figure(figsize=(11.0, sum(heights) + 0.3))
    top = fig.get_figheight() - 0.15
    for tr, h in zip(traces, heights):
        ax = fig.add_axes([0.07, (top - h + 0.5) / fig.get_figheight(), 0.78,
                           (h - 0.8) / fig.get_figheight()])
        draw_trajectories(ax, tr)
        top -= h
    return fig


def ca_panels(traces: Sequence[Trace]) -> Figure:
    cols = 2 if len(traces) > 1 else 1
    rows = math.ceil(len(traces) / cols)
    fig, axes = _pyplot().subplots(rows, cols, figsize=(6.0 * cols, 3.0 * rows), squeeze=False)
    fig.subplots_adjust(hspace=0.45, wspace=0.28, left=0.08, right=0.97, top=0.93, bottom=0.1)
    fig.suptitle("Contributing distances (CA)", fontsize=11)
    for ax, tr in zip(axes.flat, traces):
        draw_ca(ax, tr, title=False)
        ax.set_title(tr.name, fontsize=9)
        ax.set_xlabel("simulated time [s]")
        ax.set_ylabel("CA [m]")
        if ax.get_lines():
            ax.legend(fontsize=7, loc="best")
    for ax in list(axes.flat)[len(traces):]:
        ax.set_visible(False)
    return fig


def save(fig: Figure, stem: Path) -> list[Path]:
    """stem.png and stem.svg (deterministic SVG: fixed hash salt, no date)."""
    stem.parent.mkdir(parents=True, exist_ok=True)
    out = []
    for fmt in FORMATS:
        path = stem.with_name(f"{stem.name}.{fmt}")
        meta = {"Date": None} if fmt == "svg" else {"Software": None}
        fig.savefig(path, format=fmt, dpi=150, metadata=meta, bbox_inches="tight",
                    pad_inches=0.1)
        out.append(path)
    _pyplot().close(fig)
    return out


def _safe_stem(name: str) -> str:
    """A file name made of a name from the log (any peer's bytes): every character but
    [A-Za-z0-9._-] becomes '_', leading '.' and '-' are dropped, at most 100 characters; "run"
    when nothing is left. The figures never leave their directory."""
    plain = string.ascii_letters + string.digits + "._-"
    s = "".join(c if c in plain else "_" for c in name)[:100].lstrip(".-")
    return s or "run"


def write_run_figures(trace: Trace, out_dir: Path) -> list[Path]:
    stem = out_dir / _safe_stem(trace.name)
    paths = save(trajectories_figure(trace), stem.with_name(stem.name + "_trajectories"))
    paths += save(ca_cm_figure(trace), stem.with_name(stem.name + "_ca_cm"))
    paths += save(cm_gamma_figure([trace]), stem.with_name(stem.name + "_cm_gamma"))
    return paths


def write_summary_figures(traces: Sequence[Trace], out_dir: Path) -> list[Path]:
    paths = save(trajectories_panels(traces), out_dir / "trajectories")
    paths += save(ca_panels(traces), out_dir / "ca")
    paths += save(cm_gamma_figure(traces), out_dir / "cm_gamma")
    return paths


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("runs", nargs="+", type=Path, metavar="RUN_DIR",
                        help="a scenario's run directory, or a directory of them (runs/latest)")
    parser.add_argument("--out", type=Path, default=None,
                        help="where every figure goes (default: each run's in its directory, "
                             "those of several runs in their common parent)")


def main(args: argparse.Namespace) -> int:
    _pyplot().rcParams["svg.hashsalt"] = "coopnav"
    try:
        runs = find_runs(args.runs)
        traces = [(d, trace_of_run(d)) for d in runs]
    except TraceError as e:
        print(f"coopnav figures: {e}", file=sys.stderr)
        return 1
    written: list[Path] = []
    for d, tr in traces:
        written += write_run_figures(tr, args.out or d)
    if len(traces) > 1:
        common = Path(os.path.commonpath([str(d.resolve().parent) for d, _ in traces]))
        written += write_summary_figures([tr for _, tr in traces], args.out or common)
    for p in written:
        print(p)
    return 0
