"""coopnav_exp.metrics: the population table from per-run metrics JSON (hand-computed values)."""

import json
import subprocess
from pathlib import Path

import pytest

from coopnav_exp import cli, metrics, stats


def run(scenario, success, ttg, persons):
    return {"scenario": scenario, "success": success, "collision": not success, "timeout": False,
            "failure_to_progress": False, "time_to_goal_s": ttg, "spl": 1.0 if success else 0.0,
            "persons": persons}


def person(pid, resp, cm, contributing):
    return {"id": pid, "robot_responsibility": None if resp is None else 1 - resp,
            "person_responsibility": resp, "cm_interaction_m": cm,
            "is_contributing_interaction": contributing}


def write(path: Path, runs):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"format": metrics.METRICS_FORMAT, "runs": runs}))


RUNS = [
    run("pop_0000", True, 30.0, [person(1, 0.9, 0.6, True)]),
    run("pop_0001", True, 34.0, [person(1, 0.2, 0.1, False)]),
    run("pop_0002", False, None, [person(1, 0.5, 0.3, True), person(2, None, 0.0, False)]),
    run("base_corridor", True, 25.0, []),
]


def test_aggregate_rates_means_and_agreement():
    table = metrics.aggregate(RUNS[:3], n_boot=200)
    by = {row["key"]: row for row in table["metrics"]}
    # 2 of 3 successes: Wilson.
    w = stats.wilson(2, 3)
    assert by["success"]["value"] == pytest.approx(2 / 3)
    assert (by["success"]["lo"], by["success"]["hi"]) == (pytest.approx(w.lo), pytest.approx(w.hi))
    assert by["success"]["method"] == "wilson"
    # Time to goal: the mean of the two that have one.
    assert by["time_to_goal_s"]["value"] == 32.0 and by["time_to_goal_s"]["n"] == 2
    assert by["min_ttc_s"]["value"] is None and by["min_ttc_s"]["n"] == 0  # absent everywhere
    persons = {row["key"]: row for row in table["persons"]}
    assert persons["person_responsibility"]["n"] == 3
    assert persons["person_responsibility"]["value"] == pytest.approx((0.9 + 0.2 + 0.5) / 3)
    agreement = {row["key"]: row for row in table["agreement"]}
    # Shares 0.9, 0.2, 0.5 against CM 0.6, 0.1, 0.3: the same order, rho 1.
    rho = agreement["spearman(person_responsibility, cm_interaction_m)"]
    assert rho["value"] == pytest.approx(1.0) and rho["n"] == 3
    # Contributing (0.9, 0.5) all above not contributing (0.2): AUC 1.
    assert agreement["auc(person_responsibility, is_contributing_interaction)"]["value"] == 1.0
    text = metrics.format_table(table)
    assert "success" in text and "Spearman rho" in text
    assert metrics.table_csv(table).splitlines()[0] == "part,key,label,method,value,lo,hi,n"


def test_command_reads_a_population_and_leaves_out_baselines(tmp_path, capsys):
    write(tmp_path / "runs" / "a" / "a.metrics.json", RUNS[:2])
    write(tmp_path / "runs" / "b" / "b.metrics.json", RUNS[2:])
    status = cli.main(["metrics", str(tmp_path), "--n-boot", "100"])
    assert status == 0
    table = json.loads((tmp_path / "metrics_table.json").read_text())
    assert table["runs"] == 3  # base_corridor left out
    assert (tmp_path / "metrics_table.csv").is_file()
    assert (tmp_path / "metrics_table.txt").read_text() == capsys.readouterr().out
    assert cli.main(["metrics", str(tmp_path), "--include-baselines", "--out",
                     str(tmp_path / "all")]) == 0
    assert json.loads((tmp_path / "all.json").read_text())["runs"] == 4


def test_logs_without_metrics_are_scored_with_their_scenario_as_map(tmp_path, monkeypatch):
    log = tmp_path / "runs" / "pop_0000" / "pop_0000.lcm"
    log.parent.mkdir(parents=True)
    log.write_bytes(b"")
    (tmp_path / "scenarios").mkdir()
    (tmp_path / "scenarios" / "pop_0000.yaml").write_text("name: pop_0000\n")
    calls = []

    def fake_run(cmd, **kwargs):
        calls.append(cmd)
        write(Path(cmd[cmd.index("--json") + 1]), RUNS[:1])
        return subprocess.CompletedProcess(cmd, 0, "", "")

    monkeypatch.setattr(metrics.subprocess, "run", fake_run)
    files = metrics.find_metrics([tmp_path], Path("/x/coopnav_ctl"))
    assert files == [log.with_name("pop_0000.metrics.json")]
    assert calls == [["/x/coopnav_ctl", "metrics", str(log), "--json", str(files[0]), "--map",
                      str(tmp_path / "scenarios" / "pop_0000.yaml")]]
    metrics.find_metrics([tmp_path], Path("/x/coopnav_ctl"))
    assert len(calls) == 1  # scored once; --rescore scores again
    metrics.find_metrics([tmp_path], Path("/x/coopnav_ctl"), rescore=True)
    assert len(calls) == 2


def test_bad_files_are_refused(tmp_path, capsys):
    (tmp_path / "x.metrics.json").write_text(json.dumps({"format": "other"}))
    assert cli.main(["metrics", str(tmp_path)]) == 2
    assert "not a coopnav-metrics/1 file" in capsys.readouterr().err
    assert cli.main(["metrics", str(tmp_path / "missing")]) == 2


def test_paired_variants_match_encounters_by_scenario(tmp_path, capsys):
    ref = [run(f"pop_{i:04d}", True, 30.0 + i, [person(1, 0.4, 0.2, False)]) for i in range(6)]
    # The variant: every encounter 2 s slower, two of six failed, the person's share higher.
    var = [run(f"pop_{i:04d}", i >= 2, 32.0 + i, [person(1, 0.6, 0.3, True)]) for i in range(6)]
    var.append(run("pop_0099", True, 1.0, []))  # not in the reference: not paired
    rows = {r["key"]: r for r in metrics.paired_table({"paper": ref, "muted": var}, n_boot=200)}
    ttg = rows["time_to_goal_s"]
    assert ttg["n_pairs"] == 6 and ttg["difference"] == pytest.approx(2.0)
    assert (ttg["lo"], ttg["hi"]) == (pytest.approx(2.0), pytest.approx(2.0))
    assert ttg["test"] == "wilcoxon-normal"  # six tied differences
    success = rows["success"]
    assert success["test"] == "mcnemar-exact"
    assert success["difference"] == pytest.approx(-2 / 6)
    assert success["p_value"] == pytest.approx(0.5)  # 2 discordant pairs: 2 × 1/4
    resp = rows["person_responsibility"]
    assert resp["n_pairs"] == 6 and resp["difference"] == pytest.approx(0.2)

    write(tmp_path / "paper" / "runs.metrics.json", ref)
    write(tmp_path / "muted" / "runs.metrics.json", var)
    assert cli.main(["metrics", "--paired", str(tmp_path / "paper"), str(tmp_path / "muted"),
                     "--out", str(tmp_path / "cmp"), "--n-boot", "100"]) == 0
    out = capsys.readouterr().out
    assert "## paired: muted - paper (same encounters)" in out
    assert "# variant paper" in out and "# variant muted" in out
    saved = json.loads((tmp_path / "cmp.json").read_text())
    assert saved["variant"] == "paper" and saved["runs"] == 6
    assert saved["variant_tables"]["muted"]["runs"] == 7
    assert "paired:muted-paper,time_to_goal_s," in (tmp_path / "cmp.csv").read_text()
    assert cli.main(["metrics", "--paired", str(tmp_path / "paper")]) == 2


def test_a_log_that_cannot_be_scored_is_reported_not_lost(tmp_path, monkeypatch, capsys):
    write(tmp_path / "runs" / "a" / "a.metrics.json", RUNS[:2])
    bad = tmp_path / "runs" / "b" / "b.lcm"
    bad.parent.mkdir(parents=True)
    bad.write_bytes(b"")

    def failing(cmd, **kwargs):
        return subprocess.CompletedProcess(cmd, 1, "", "b.lcm: no agent states, no tracks")

    monkeypatch.setattr(metrics.subprocess, "run", failing)
    with pytest.raises(RuntimeError):
        metrics.find_metrics([tmp_path], Path("ctl"))
    assert cli.main(["metrics", str(tmp_path), "--n-boot", "50"]) == 0
    captured = capsys.readouterr()
    assert "not scored" in captured.err and "no agent states" in captured.err
    assert captured.out.startswith("# 1 logs could not be scored")
    table = json.loads((tmp_path / "metrics_table.json").read_text())
    assert table["runs"] == 2 and len(table["unscored"]) == 1


def test_a_runs_own_metrics_json_is_read_not_scored_again(tmp_path, monkeypatch):
    # run_one writes DIR/metrics.json beside summary.json and the log.
    log = tmp_path / "runs" / "pop_0000" / "pop_0000.lcm"
    log.parent.mkdir(parents=True)
    log.write_bytes(b"")
    write(log.parent / "metrics.json", RUNS[:1])
    calls = []
    monkeypatch.setattr(metrics.subprocess, "run", lambda cmd, **kw: calls.append(cmd))
    assert metrics.find_metrics([tmp_path], Path("ctl")) == [log.parent / "metrics.json"]
    assert calls == []
    assert metrics.load_runs(metrics.find_metrics([tmp_path], Path("ctl")))[0]["scenario"] == \
        "pop_0000"


def test_roc_points_enclose_the_auc():
    scores = [0.9, 0.8, 0.8, 0.4, 0.3, 0.1]
    labels = [True, True, False, True, False, False]
    fpr, tpr = metrics.roc_points(scores, labels)
    assert (fpr[0], tpr[0], fpr[-1], tpr[-1]) == (0.0, 0.0, 1.0, 1.0)
    # Trapezoids (a tie moves both rates at once): the Mann-Whitney AUC, ties counting half.
    area = sum((fpr[i + 1] - fpr[i]) * (tpr[i + 1] + tpr[i]) / 2 for i in range(len(fpr) - 1))
    assert area == pytest.approx(stats.auc(scores, labels))
    # By hand: 0.9 beats 3 negatives, 0.8 ties one and beats 2, 0.4 beats 2: 7.5 of 9 pairs.
    assert area == pytest.approx(7.5 / 9)
    assert metrics.roc_points([0.1, 0.2], [True, True]) == ([], [])


def test_agreement_figure_is_drawn_only_where_there_is_cm(tmp_path):
    files = metrics.agreement_figure(RUNS, tmp_path / "agreement", n_boot=50, title="t")
    assert sorted(p.name for p in files) == ["agreement.png", "agreement.svg"]
    assert all(p.stat().st_size > 1000 for p in files)
    xs, ys, verdicts = metrics.agreement_points(RUNS)
    # pop_0002's second person has no share: left out; the others in run order.
    assert (xs, ys, verdicts) == ([0.9, 0.2, 0.5], [0.6, 0.1, 0.3], [True, False, True])
    no_cm = [run("pop_0000", True, 30.0, [person(1, 0.9, None, None)])]
    assert metrics.agreement_figure(no_cm, tmp_path / "none") == []
    assert not (tmp_path / "none.png").exists()
