"""The main job end to end, as a user runs it: scripts/run.sh over the paper's four scenarios
(real processes, lockstep, LCM logs), twice. Checks the paper's claims on the results
(CM(facilitating) > tau > CM(minimal) in both corridors, narrow + minimal docks without a
collision, facilitating humans are thanked, round 1 >= 3 s before crossing and every cue's words
ended before it), that the two runs give identical transcripts and CM values, that they are the
golden transcripts (test/data/golden), and that replaying a recorded log into fresh assessors
and dialogue manager reproduces the recorded transcript."""

import difflib
import os
import subprocess

from conftest import run_sh, scenarios_of

PAPER = ("open_facilitating", "open_minimal", "narrow_facilitating", "narrow_minimal")


def print_diff(a: str, b: str, n: int = 30) -> None:
    print("".join(list(difflib.unified_diff(a.splitlines(True), b.splitlines(True)))[:n]))


def human(s):
    hs = s["humans"]
    assert len(hs) == 1, f"{s['scenario']}: expected one human, got {len(hs)}"
    return hs[0]


def test_the_paper_scenarios_twice_and_a_replay(tmp_path, source_dir, port_base):
    run_sh(source_dir, tmp_path / "a", port=port_base)
    run_sh(source_dir, tmp_path / "b", port=port_base + 10)
    print((tmp_path / "a" / "cm_table.txt").read_text())
    bad = []
    for n in PAPER:
        ta = (tmp_path / "a" / n / "transcript.txt").read_text()
        tb = (tmp_path / "b" / n / "transcript.txt").read_text()
        if ta != tb:
            bad.append(f"{n}: transcripts of two runs differ")
            print_diff(ta, tb)
        # The golden replay's transcripts are those of a lockstep run (test/data/golden): the
        # run gives them to the byte.
        golden = source_dir / "test/data/golden" / f"{n}.transcript"
        if golden.is_file() and ta != golden.read_text():
            bad.append(f"{n}: transcript differs from {golden.relative_to(source_dir)}")

    a, b = scenarios_of(tmp_path / "a/summary.json"), scenarios_of(tmp_path / "b/summary.json")
    for corridor in ("open", "narrow"):
        fac, mini = human(a[corridor + "_facilitating"]), human(a[corridor + "_minimal"])
        cf, cmn, tau = fac["cm_interaction_m"], mini["cm_interaction_m"], fac["tau_m"]
        print(f"{corridor}: CM facilitating {cf}, minimal {cmn}, tau {tau}")
        if cf is None or cmn is None or not cf > tau > cmn:
            bad.append(f"{corridor}: want CM(facilitating) > tau > CM(minimal), got {cf}, "
                       f"{tau}, {cmn}")
        if not fac["thanked"]:
            bad.append(f"{corridor}_facilitating: the facilitating human was not thanked")
    if not human(a["narrow_minimal"])["docked"]:
        bad.append("narrow_minimal: the robot did not dock")
    for name, s in a.items():
        if s["collision"]:
            bad.append(f"{name}: collision ({s['detail']})")
        for h in s["humans"]:
            for e in h["transcript"]:
                if (e.get("kind", "say") == "say" and e.get("round") in (1, 2)
                        and e.get("delivery", "said") == "said"):
                    # Round 1 early enough to be acted on; every said cue's words end before the
                    # crossing (round 2 may wait for the response to round 1 until t_CROSS 3 s).
                    if e["round"] == 1 and (e["t_cross_s"] is None or e["t_cross_s"] < 3.0):
                        bad.append(f"{name}: round 1 at t={e['t_s']} given {e['t_cross_s']} s "
                                   "before crossing")
                    if not (e.get("lead_s") is not None and e["lead_s"] > 0.0):
                        bad.append(f"{name}: cue at t={e['t_s']} ends {e.get('lead_s')} s "
                                   "before crossing")
        for ha, hb in zip(s["humans"], b[name]["humans"]):
            for key in ("cm_interaction_m", "cm_window_m", "docked", "thanked"):
                if ha[key] != hb[key]:
                    bad.append(f"{name}: {key} differs between runs: {ha[key]} vs {hb[key]}")

    # Replay: the recorded world into fresh assessors + dialogue manager gives the same
    # transcript.
    log = tmp_path / "a/narrow_minimal/narrow_minimal.lcm"
    r = subprocess.run(["bash", str(source_dir / "scripts/replay.sh"), "--no-build", "--speed",
                        "1", "--out-dir", str(tmp_path / "replay"), str(log)],
                       env=dict(os.environ, COOPNAV_REPLAY_PORT=str(port_base + 20)),
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        bad.append(f"replay.sh exited {r.returncode}: {r.stderr}")
    elif r.stdout != (tmp_path / "a/narrow_minimal/transcript.txt").read_text():
        bad.append("replayed transcript differs from the recorded one")
        print_diff((tmp_path / "a/narrow_minimal/transcript.txt").read_text(), r.stdout)
    assert not bad
