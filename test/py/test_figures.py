"""figures.py on a small synthetic trace (no process): the files, the walls, the labels."""

from __future__ import annotations

import argparse
import itertools
import json
import math
from pathlib import Path

import matplotlib
import pytest

from coopnav_exp import figures

matplotlib.use("Agg")


def corridor_trace(name: str = "narrow_test", *, humans: int = 1, grid: bool = False) -> dict:
    """A robot and people crossing in a 2.25 m corridor (walls at y 0 and 2.25), 20 s at 10 Hz,
    with two utterances, a dock, and CA / CM per person: the shape `coopnav_ctl trace` writes."""
    t = [k * 0.1 for k in range(201)]
    robot_x = [1.0 + 0.7 * s for s in t]
    robot_y = [1.125 - (0.5 if 8.0 <= s <= 12.0 else 0.0) for s in t]
    people = []
    for i in range(humans):
        people.append({"id": i + 1, "t_s": t, "x_m": [15.0 - 0.8 * s for s in t],
                       "y_m": [1.125 + 0.1 * i + (0.3 if s > 6 else 0.0) for s in t],
                       "theta_rad": [math.pi] * len(t), "radius_m": 0.3})
    assessments = []
    for i in range(humans):
        ts = [4.0 + 0.1 * k for k in range(80)]
        ca = [0.005 * k for k in range(80)]
        assessments.append({
            "id": i + 1, "t_s": ts, "cm_m": [0.003 * k for k in range(80)],
            "cm_interaction_m": [0.003 * k for k in range(80)],
            "is_contributing": [k > 60 for k in range(80)], "tau_m": [0.4] * 80,
            "p_contributing": [None] * 80, "gamma": 0.98, "tau_fixed_m": 0.4, "profile": "paper",
            "ca": {"whole_interaction": True, "t_s": ts, "ca_m": ca, "window_start_t_s": [7.0]},
            "cm_by_gamma": {"gamma": [0.5 + 0.01 * k for k in range(51)],
                            "cm_m": [0.1 + 0.002 * k for k in range(51)]},
            "first_round": {"t_s": 4.0, "t_cross_s": 6.9, "cp_h_m": [8.0, 1.4],
                            "cp_r_m": [8.0, 0.8]},
        })
    words = [(4.0, "INFORM_DOCK_IF_NEEDED", "It is narrow here. I will wait at the side if needed."),
             (7.0, "INFORM_DOCKING", "I will wait here for you to pass."),
             (7.1, "THANK", "Thank you.")]
    m = {"path": "/x/narrow_test.yaml", "source": "narrow_test.yaml: map", "file": None,
         "walls": [[-1.0, 0.0, 20.0, 0.0], [-1.0, 2.25, 20.0, 2.25]], "boxes": [],
         "resolution_m": 0.05, "origin_m": [-1.1, -0.1], "width": 0, "height": 0,
         "obstacle_runs": []}
    if grid:
        # The same corridor as a grid only (a ROS map): 0.05 m cells, walls 0.2 m thick.
        m.update(walls=[], width=440, height=50, obstacle_runs=[[j, 0, 440] for j in (0, 1, 2, 3)]
                 + [[j, 0, 440] for j in (45, 46, 47, 48, 49)])
    return {
        "format": "coopnav-trace", "version": 1, "scenario": name, "log": f"{name}.lcm",
        "robot": {"t_s": t, "x_m": robot_x, "y_m": robot_y, "theta_rad": [0.0] * len(t),
                  "radius_m": 0.47},
        "humans": people, "assessments": assessments,
        "utterances": [{"t_s": s, "human_id": 1, "act": act, "round": 1 + (k > 0), "direction":
                        "left", "t_cross_s": 3.0, "text": txt, "delivery": "said", "said": True,
                        "speech_start_s": 0.0, "speech_duration_s": 2.0}
                       for k, (s, act, txt) in enumerate(words)],
        "actions": [{"t_s": 7.0, "action": "DOCK", "human_id": 1, "reason": "round 2"}],
        "modes": [{"t_s": 0.0, "mode": "navigating"}, {"t_s": 7.1, "mode": "docking"},
                  {"t_s": 8.0, "mode": "holding"}, {"t_s": 12.0, "mode": "resuming"}],
        "recorder": [], "outcome": None, "map": m,
    }


def write_run(tmp: Path, doc: dict) -> Path:
    d = tmp / doc["scenario"]
    d.mkdir(parents=True)
    (d / "trace.json").write_text(json.dumps(doc))
    return d


def test_runs_write_png_and_svg_of_each_figure_and_the_figures_across_runs(tmp_path):
    for name in ("open_a", "narrow_b"):
        write_run(tmp_path / "run", corridor_trace(name))
    assert figures.main(argparse.Namespace(runs=[tmp_path / "run"], out=None)) == 0
    # Each run's figures in its directory, those across runs in their common parent.
    stems = [f"run/{n}/{n}_{fig}" for n in ("open_a", "narrow_b")
             for fig in ("trajectories", "ca_cm", "cm_gamma")]
    stems += ["run/trajectories", "run/ca", "run/cm_gamma"]
    for stem in stems:
        assert (tmp_path / f"{stem}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert "<svg" in (tmp_path / f"{stem}.svg").read_text()
    # The walls are in the SVG as a group of their own.
    assert 'id="walls' in (tmp_path / "run/open_a/open_a_trajectories.svg").read_text()


@pytest.mark.parametrize("grid", [False, True])
def test_walls_are_drawn_where_the_map_has_them(grid):
    tr = figures.trace_from_doc(corridor_trace(grid=grid))
    fig = figures.trajectories_figure(tr)
    ax = fig.axes[0]
    walls = [a for a in ax.get_children() if a.get_gid() == "walls"]
    assert walls, "no wall drawn"
    ys = []
    for a in walls:
        if hasattr(a, "get_ydata"):
            ys += list(a.get_ydata())
        else:
            for p in a.get_paths():
                ys += list(p.vertices[:, 1])
    # The two walls: near y = 0 and y = 2.25 (a grid's contour runs along the cells' edges).
    assert min(ys) < 0.3 and max(ys) > 1.95
    assert any(abs(y) < 0.3 for y in ys) and any(abs(y - 2.25) < 0.3 for y in ys)


def test_no_two_labels_overlap_in_any_figure():
    tr = figures.trace_from_doc(corridor_trace(humans=3))
    for fig in (figures.trajectories_figure(tr), figures.ca_cm_figure(tr),
                figures.cm_gamma_figure([tr])):
        assert figures.label_boxes_overlap(fig) == []
        placed = sum(len(ax.texts) for ax in fig.axes)
        assert placed > 0


def test_the_placer_refuses_a_place_taken():
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(3, 2))
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    placer = figures.LabelPlacer(ax)
    labels = [placer.place(f"label {k}", 0.5, 0.5, fontsize=9) for k in range(30)]
    kept = [t for t in labels if t is not None]
    assert 1 < len(kept) < 30  # the crowded ones are left out rather than drawn over others
    r = fig.canvas.get_renderer()
    for a, b in itertools.combinations(kept, 2):
        assert not a.get_window_extent(r).overlaps(b.get_window_extent(r))
    plt.close(fig)


def test_a_directory_without_runs_is_an_error(tmp_path, capsys):
    assert figures.main(argparse.Namespace(runs=[tmp_path], out=None)) == 1
    assert "not a run directory" in capsys.readouterr().err


def test_a_file_that_is_not_a_trace_is_refused(tmp_path):
    d = tmp_path / "x"
    d.mkdir()
    (d / "trace.json").write_text('{"scenarios": []}')
    with pytest.raises(figures.TraceError):
        figures.trace_of_run(d)


def test_a_name_from_the_log_never_leaves_the_directory(tmp_path, monkeypatch):
    # The scenario name in a trace comes from the log, i.e. from any peer on the bus.
    for name in ("../../escaped", "/tmp/absolute", "..", ".hidden", "-rf", "a/b\\c\nd\x1bé",
                 "n" * 500, ""):
        stem = figures._safe_stem(name)
        assert stem and len(stem) <= 100 and stem[0] not in ".-"
        assert set(stem) <= set("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-")
    assert figures._safe_stem("open_facilitating") == "open_facilitating"
    assert figures._safe_stem("../../escaped") == "_.._escaped"
    assert figures._safe_stem("..") == "run"
    monkeypatch.setattr(figures, "FORMATS", ("svg",))
    tr = figures.trace_from_doc(corridor_trace("../../escaped"))
    out = tmp_path / "out"
    paths = figures.write_run_figures(tr, out)
    assert paths and all(p.parent == out for p in paths)
    assert not (tmp_path / "escaped_trajectories.png").exists()


def test_commands_other_than_figures_do_not_import_matplotlib(source_dir):
    # matplotlib's import (~0.3 s) is paid where a figure is drawn, not by every command.
    import subprocess
    import sys
    code = "import sys, coopnav_exp.cli; sys.exit('matplotlib' in sys.modules)"
    p = subprocess.run([sys.executable, "-c", code],
                       env={"PYTHONPATH": str(source_dir / "tools" / "exp")})
    assert p.returncode == 0, "importing coopnav_exp.cli imported matplotlib"
