"""The fault verdicts (same / degraded / FAIL) from summary.json entries: each rule of the
README's "Faults" on a run that keeps it and one that breaks it."""

from __future__ import annotations

import copy

import pytest

from coopnav_exp import faults


def entry(*, state="GOAL_REACHED", docks=(), unknown=0, restarts=(), say_text="Pass left.",
          cm=0.61, t_dock=12.0):
    transcript = [{"kind": "say", "t_s": 5.0, "t_cross_s": 7.0, "act": "INFORM_DIRECTION",
                   "text": say_text, "round": 1, "direction": "LEFT", "delivery": "said"}]
    for degraded in docks:
        transcript.append({"kind": "action", "t_s": t_dock, "t_cross_s": 3.0, "action": "DOCK",
                           "reason": "x", "degraded": degraded})
    return {"final_state": state, "last_step": 300, "min_clearance_m": 0.4,
            "robot_time_to_goal_s": 30.0,
            "humans": [{"id": 1, "transcript": transcript, "cm_window_m": cm,
                        "window_samples": 20, "is_contributing": True, "cm_interaction_m": cm,
                        "interaction_samples": 30, "is_contributing_interaction": True,
                        "gamma": 0.98, "tau_m": 0.3}],
            "faults": {"restarts": list(restarts), "degraded_daemons": [],
                       "crossing_situations": 50, "crossing_distance_unknown": unknown}}


def judge(kind, e, clean, **kw):
    kw.setdefault("world_exit", 0)
    return faults.judge(kind, e, clean, **kw)


CLEAN = entry()


def test_a_clean_run_is_ok_unless_it_failed():
    assert judge("clean", CLEAN, None).verdict == "ok"
    v = judge("clean", None, None, world_exit=1)
    assert (v.verdict, v.detail) == ("FAIL", "world_sim exit 1")
    assert judge("clean", CLEAN, None, start_error="x exited at start").verdict == "FAIL"


@pytest.mark.parametrize("kind", ["kill", "absent", "loss"])
def test_same_decisions_are_same(kind):
    e = entry(unknown=40 if kind == "absent" else 0)
    assert judge(kind, e, CLEAN).verdict == "same"


def test_decisions_at_the_transcripts_precision():
    e = copy.deepcopy(CLEAN)
    e["humans"][0]["cm_window_m"] += 1e-6  # below the transcript's 3 decimals
    assert judge("loss", e, CLEAN).verdict == "same"
    e["humans"][0]["cm_window_m"] += 0.01
    assert judge("loss", e, CLEAN).verdict == "FAIL"


def test_a_daemon_dying_on_its_own_or_a_bad_end_fails():
    assert judge("kill", CLEAN, CLEAN, died=["path_assessor"]).detail == \
        "died on its own: path_assessor"
    for state in ("PARTICIPANT_TIMEOUT", "COLLISION", None):
        assert judge("kill", entry(state=state), CLEAN).verdict == "FAIL"


def test_loss_must_keep_the_decisions():
    v = judge("loss", entry(say_text="Pass right."), CLEAN)
    assert (v.verdict, v.detail) == ("FAIL",
                                     "decisions differ from the clean run's under message loss")


def test_kill_degraded_only_when_the_run_says_why():
    assert judge("kill", entry(say_text="Other."), CLEAN).verdict == "FAIL"
    lost = [{"participant": "dialogue_manager", "step": 40, "recovered": False,
             "note": "state lost"}]
    v = judge("kill", entry(say_text="Other.", restarts=lost), CLEAN)
    assert v.verdict == "degraded"
    assert "dialogue_manager restarted at step 40" in v.detail
    # A recovered restart is no excuse for other decisions.
    ok = [dict(lost[0], recovered=True)]
    assert judge("kill", entry(say_text="Other.", restarts=ok), CLEAN).verdict == "FAIL"
    # More crossings with unknown distances than the clean run: the server did not answer.
    v = judge("kill", entry(say_text="Other.", unknown=3), CLEAN)
    assert (v.verdict, v.detail.startswith("distance server")) == ("degraded", True)


def test_no_dock_the_clean_run_did_not_have_unless_precautionary():
    v = judge("kill", entry(docks=[False]), CLEAN)
    assert (v.verdict, v.detail) == ("FAIL", "a dock the clean run did not have: human 1")
    v = judge("kill", entry(docks=[True], unknown=5), CLEAN)
    assert v.verdict == "degraded" and "precautionary dock" in v.detail
    # The clean run docked too: another time of the same dock is a degraded run, not a false one.
    clean_dock = entry(docks=[False])
    lost = [{"participant": "band_source", "step": 9, "recovered": False, "note": "n"}]
    assert judge("kill", entry(docks=[False], t_dock=13.0, restarts=lost),
                 clean_dock).verdict == "degraded"


def test_absent_server():
    # Every dock a precaution, the situations say the distances are unknown.
    v = judge("absent", entry(docks=[True], unknown=40), CLEAN)
    assert v.verdict == "degraded"
    assert judge("absent", entry(docks=[False], unknown=40), CLEAN).detail == \
        "docked without the distance server, not as a precaution"
    assert judge("absent", entry(docks=[True], unknown=0), CLEAN).detail == \
        "the situations do not say the obstacle distances are unknown"


def test_first_differences():
    a = faults.decisions(CLEAN)
    b = faults.decisions(entry(say_text="Other."))
    d = faults.first_differences(a, b)
    assert len(d) == 2 and d[0].startswith("- ") and "Other." in d[1]
