"""The multihost verdicts (tools/exp/coopnav_exp/multihost.py) from summary.json entries: the
drop-off rules of README "Network and hosts" on a run that keeps each and one that breaks it,
the drop step, and the transcripts compared as files."""

from __future__ import annotations

import copy

from coopnav_exp import multihost


def say(t, hid, rnd, text):
    return {"kind": "say", "t_s": t, "t_cross_s": 7.0 - t, "act": "INFORM_DIRECTION",
            "text": text, "round": rnd, "direction": "LEFT", "delivery": "said"}


def entry(*, state="GOAL_REACHED", last=None, degraded=(), transcript=None, last_step=300):
    transcript = transcript if transcript is not None else [
        say(5.0, 1, 1, "I will pass on your left."), say(9.0, 1, 2, "Please move more.")]
    return {"final_state": state, "last_step": last_step, "detail": "",
            "min_clearance_m": 0.4, "robot_time_to_goal_s": 30.0,
            "humans": [{"id": 1, "transcript": transcript}],
            "faults": {"restarts": [], "crossing_situations": 50, "crossing_distance_unknown": 0,
                       "degraded_daemons": [{"name": n, "detail": f"step 71 ran without {w}"}
                                            for n, w in degraded],
                       "last_acked_step": last or {}}}


REF = entry(last={"world_sim": 300, "path_assessor": 300, "dialogue_manager": 300})
CUT = {"world_sim": 71, "path_assessor": 70, "dialogue_manager": 71, "band_source": 71,
       "situation_assessor": 71}


def dropoff(**kw):
    kw.setdefault("state", "PARTICIPANT_TIMEOUT")
    kw.setdefault("last", CUT)
    kw.setdefault("degraded", [("dialogue_manager", "path_assessor")])
    kw.setdefault("transcript", [say(5.0, 1, 1, "I will pass on your left.")])
    kw.setdefault("last_step", 71)
    return entry(**kw)


def test_drop_step_is_halfway_between_the_rounds_and_has_a_default():
    assert multihost.drop_step(REF) == 70
    assert multihost.drop_step(entry(transcript=[say(5.0, 1, 1, "x")])) == 100
    assert multihost.drop_step(None, default=42) == 42


def test_a_dropoff_that_stops_the_world_and_says_so_is_ok():
    v = multihost.judge_dropoff(dropoff(), REF)
    assert v.verdict == "ok", v.detail
    assert "path_assessor last acknowledged step 70" in v.detail


def test_a_dropoff_the_world_went_on_without_fails():
    v = multihost.judge_dropoff(dropoff(state="GOAL_REACHED"), REF)
    assert v.verdict == "FAIL" and "participant timeout" in v.detail


def test_a_timeout_for_another_participant_fails():
    last = dict(CUT, path_assessor=71, band_source=69)
    v = multihost.judge_dropoff(dropoff(last=last), REF)
    assert v.verdict == "FAIL" and "not the participant the world waited for" in v.detail


def test_a_dialogue_manager_that_did_not_go_on_or_never_said_degraded_fails():
    v = multihost.judge_dropoff(dropoff(last=dict(CUT, dialogue_manager=70)), REF)
    assert v.verdict == "FAIL" and "did not run without" in v.detail
    v = multihost.judge_dropoff(dropoff(degraded=[]), REF)
    assert v.verdict == "FAIL" and "never DEGRADED" in v.detail


def test_decisions_must_be_the_first_ones_of_the_single_host_run():
    other = [say(5.0, 1, 1, "I will pass on your right.")]
    v = multihost.judge_dropoff(dropoff(transcript=other), REF)
    assert v.verdict == "FAIL" and "decisions differ" in v.detail
    extra = [say(5.0, 1, 1, "I will pass on your left."), say(6.0, 1, 2, "Please move more.")]
    v = multihost.judge_dropoff(dropoff(transcript=extra), REF)
    assert v.verdict == "FAIL"
    assert multihost.judge_dropoff(None, REF).verdict == "FAIL"
    assert multihost.judge_dropoff(dropoff(), None).verdict == "FAIL"


def test_said_leaves_out_the_final_cms_and_the_end_of_the_run():
    s = multihost.said(copy.deepcopy(REF))
    assert list(s) == [1] and len(s[1]) == 2


def test_transcripts_are_compared_byte_for_byte(tmp_path):
    a, b, c = tmp_path / "a", tmp_path / "b", tmp_path / "c"
    a.write_text("t=1.00s SAY x\n")
    b.write_text("t=1.00s SAY x\n")
    c.write_text("t=1.00s SAY x \n")
    assert multihost.judge_same_transcript(a, b).verdict == "same"
    assert multihost.judge_same_transcript(a, c).verdict == "FAIL"
    assert multihost.judge_same_transcript(a, tmp_path / "missing").verdict == "FAIL"
