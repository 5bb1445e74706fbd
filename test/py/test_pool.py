"""coopnav_exp.pool with small Python processes: slots and ports, order, the wall timeout that
stops a run's whole process group."""

from __future__ import annotations

import os
import sys
import time

from coopnav_exp import pool


def job(tmp_path, name, code):
    return pool.Job(name, lambda port: [sys.executable, "-c", code, str(port)],
                    tmp_path / f"{name}.log")


def test_ports_per_slot_and_results_in_order(tmp_path):
    code = ("import sys, time; open(sys.argv[0] if False else %r + '/' + sys.argv[1], 'a')"
            ".close(); time.sleep(0.3)") % str(tmp_path)
    jobs = [job(tmp_path, f"j{i}", code) for i in range(5)]
    seen = []
    results = pool.Pool(2, 7400, timeout_s=30).run(
        jobs, lambda r, done, total: seen.append((r.job.name, done, total)))
    assert [r.job.name for r in results] == [f"j{i}" for i in range(5)]
    assert all(r.returncode == 0 and not r.timed_out for r in results)
    # Two at a time: only the ports of slots 0 and 1, never one port twice at once.
    assert {r.port for r in results} == {7400, 7401}
    assert {p.name for p in tmp_path.iterdir() if p.name.isdigit()} == {"7400", "7401"}
    assert [d for _, d, _ in seen] == [1, 2, 3, 4, 5] and seen[0][2] == 5


def test_timeout_stops_the_run_and_its_children(tmp_path):
    pidfile = tmp_path / "child.pid"
    # The run starts a child (as a run starts its daemons) and outlives its timeout.
    code = ("import subprocess, sys, time; c = subprocess.Popen([sys.executable, '-c', "
            "'import time; time.sleep(60)']); open(%r, 'w').write(str(c.pid)); time.sleep(60)"
            ) % str(pidfile)
    start = time.monotonic()
    [r] = pool.Pool(1, 7400, timeout_s=1.0, kill_after_s=2.0).run([job(tmp_path, "slow", code)])
    assert r.timed_out and r.returncode != 0
    assert time.monotonic() - start < 10
    child = int(pidfile.read_text())
    for _ in range(50):
        try:
            os.kill(child, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        raise AssertionError("the run's child outlived the timeout")
