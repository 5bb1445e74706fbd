"""Process supervision with dummy processes (no daemon): logs, readiness, a process dying at
start, SIGTERM then SIGKILL after the grace, and no orphan when the launcher is interrupted or
killed."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from coopnav_exp import supervise
from coopnav_exp.supervise import StartError, Supervisor

PY = sys.executable


def alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # A zombie is dead too (reaped later by its parent).
    try:
        return Path(f"/proc/{pid}/stat").read_text().split()[2] != "Z"
    except OSError:
        return False


def wait_until(cond, timeout_s: float = 5.0) -> bool:
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        if cond():
            return True
        time.sleep(0.02)
    return cond()


def test_output_goes_to_the_log_and_a_restart_appends(tmp_path: Path):
    with Supervisor(grace_s=1) as sup:
        # Flushed: a file is block-buffered, so unflushed 'out' would land after 'err'.
        code = "import sys; print('out', flush=True); print('err', file=sys.stderr)"
        p = sup.start("a", [PY, "-c", code], tmp_path / "a.log")
        p.popen.wait()
        sup.start("a", [PY, "-c", "print('again')"], tmp_path / "a.log").popen.wait()
    assert (tmp_path / "a.log").read_text().split() == ["out", "err", "again"]


def test_stop_all_sigterm_then_sigkill_after_the_grace(tmp_path: Path):
    stubborn = textwrap.dedent("""
        import signal, time
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        print('ready', flush=True)
        time.sleep(60)""")
    polite = "import time; print('ready', flush=True); time.sleep(60)"
    sup = Supervisor(grace_s=0.5)
    a = sup.start("stubborn", [PY, "-c", stubborn], tmp_path / "s.log")
    b = sup.start("polite", [PY, "-c", polite], tmp_path / "p.log")
    assert wait_until(lambda: "ready" in a.log.read_text() and "ready" in b.log.read_text())
    t0 = time.monotonic()
    sup.stop_all()
    took = time.monotonic() - t0
    assert b.returncode == -signal.SIGTERM
    assert a.returncode == -signal.SIGKILL
    assert 0.4 < took < 5.0


def test_wait_ready_reports_a_process_dying_at_start_at_once(tmp_path: Path):
    with Supervisor(grace_s=1) as sup:
        sup.start("bad", [PY, "-c", "import sys; print('bad map: resolution_m'); sys.exit(3)"],
                  tmp_path / "bad.log")
        sup.start("good", [PY, "-c", "import time; time.sleep(30)"], tmp_path / "good.log")
        t0 = time.monotonic()
        with pytest.raises(StartError) as ex:
            sup.wait_ready([PY, "-c", "import time; time.sleep(30)"], ["bad", "good"])
        assert time.monotonic() - t0 < 5
    assert "bad exited at start (status 3)" in str(ex.value)
    assert "bad: bad map: resolution_m" in str(ex.value)


def test_wait_ready_returns_when_the_waiter_does_and_fails_with_it(tmp_path: Path):
    with Supervisor(grace_s=1) as sup:
        sup.start("d", [PY, "-c", "import time; time.sleep(30)"], tmp_path / "d.log")
        sup.wait_ready([PY, "-c", "pass"], ["d"])
        with pytest.raises(StartError, match="status 4"):
            sup.wait_ready([PY, "-c", "import sys; sys.exit(4)"], ["d"])


LAUNCHER = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    from coopnav_exp.supervise import Supervisor, signals_stop, Interrupted
    out = Path(sys.argv[1])
    try:
        with signals_stop(), Supervisor(grace_s=1) as sup:
            for n in ("x", "y"):
                p = sup.start(n, [sys.executable, "-c", "import time; time.sleep(60)"],
                              out / f"{n}.log")
                (out / f"{n}.pid").write_text(str(p.pid))
            (out / "started").write_text("")
            time.sleep(60)
    except Interrupted as ex:
        sys.exit(ex.exit_status)
""")


@pytest.mark.parametrize("sig, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143),
                                         (signal.SIGKILL, -9)])
def test_no_orphans_when_the_launcher_is_stopped(tmp_path: Path, source_dir: Path, sig, status):
    env = dict(os.environ, PYTHONPATH=str(source_dir / "tools" / "exp"))
    launcher = subprocess.Popen([PY, "-c", LAUNCHER, str(tmp_path)], env=env)
    try:
        assert wait_until(lambda: (tmp_path / "started").exists(), 10)
        pids = [int((tmp_path / f"{n}.pid").read_text()) for n in ("x", "y")]
        assert all(alive(p) for p in pids)
        launcher.send_signal(sig)
        assert launcher.wait(10) == status
        # SIGKILL: the kernel's parent-death signal stops them.
        assert wait_until(lambda: not any(alive(p) for p in pids), 5)
    finally:
        if launcher.poll() is None:
            launcher.kill()


def test_ports_are_consecutive_blocks():
    p = supervise.Ports(20000, stride=10)
    assert [p.take(), p.take(), p.take()] == [20000, 20010, 20020]
    with pytest.raises(ValueError):
        supervise.Ports(80)


def test_wait_for_line_returns_at_once_when_the_line_is_there(tmp_path: Path):
    f = tmp_path / "record.log"
    f.write_text("coopnav_record: recording 'COOPNAV_.*' into x.lcm\n")
    t0 = time.monotonic()
    assert supervise.wait_for_line(f, "coopnav_record: recording", 5.0)
    assert time.monotonic() - t0 < 0.5
    assert not supervise.wait_for_line(tmp_path / "none.log", "recording", 0.05)


def test_a_waiter_started_first_listens_before_its_daemons_start(tmp_path: Path):
    # The waiter prints a line once it listens, then waits for what it waits for (here a file
    # the "daemon" writes): start_waiter returns in between, so nothing the daemon says is lost.
    flag = tmp_path / "said"
    waiter_src = textwrap.dedent(f"""
        import os, sys, time
        print("listening", flush=True)
        while not os.path.exists({str(flag)!r}):
            time.sleep(0.01)""")
    with Supervisor(grace_s=1) as sup:
        t0 = time.monotonic()
        waiter = sup.start_waiter([PY, "-c", waiter_src], timeout_s=10)
        assert waiter.poll() is None
        sup.start("d", [PY, "-c", f"open({str(flag)!r}, 'w'); import time; time.sleep(30)"],
                  tmp_path / "d.log")
        sup.wait_ready(waiter, ["d"], poll_s=5.0)  # returns with the waiter, not after poll_s
        assert time.monotonic() - t0 < 4.0
        # A waiter that never listens (an old coopnav_ctl without --announce) is said at once.
        with pytest.raises(StartError, match="did not start listening.*no such option"):
            sup.start_waiter([PY, "-c", "import sys; sys.exit('no such option')"], timeout_s=10)
