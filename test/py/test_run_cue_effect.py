"""The spoken cue turns a dock into a pass: test/data/scenarios/cue_narrow_responsive (a 2.75 m
corridor, narrow in the paper's sense of < 3 m, and a responsive person who hears and complies)
run by scripts/run.sh twice, speaking and with the dialogue manager muted. Muted, the person
keeps its line and the robot docks at round 2. Speaking, the person hears round 1's "I will pass
on your right.", keeps to its other side, and the robot passes without docking. What each person
heard comes from world_sim's cue outcomes (`cue_outcomes_file`, one JSON object a cue)."""

import json

from conftest import run_sh, said_lines, scenarios_of

NAME = "cue_narrow_responsive"


def test_the_spoken_cue_turns_the_dock_into_a_pass(tmp_path, source_dir, port_base):
    scenario = source_dir / "test/data/scenarios" / f"{NAME}.yaml"
    cues = {label: tmp_path / f"{label}_cue_outcomes.jsonl" for label in ("speaking", "muted")}
    run_sh(source_dir, tmp_path / "speaking", scenario, port=port_base,
           env={"COOPNAV_DAEMON_ARGS_world_sim": f"--set cue_outcomes_file={cues['speaking']}"})
    run_sh(source_dir, tmp_path / "muted", scenario, port=port_base + 10,
           env={"COOPNAV_DAEMON_ARGS_dialogue_manager": "--set muted=true",
                "COOPNAV_DAEMON_ARGS_world_sim": f"--set cue_outcomes_file={cues['muted']}"})
    heard = {}
    for label in ("speaking", "muted"):
        print(f"{label}:\n{said_lines(tmp_path / label / NAME / 'transcript.txt')}")
        outcomes = [json.loads(l) for l in cues[label].read_text().splitlines()]
        print(f"{label}: cue outcomes {outcomes}")
        heard[label] = [o for o in outcomes if o["heard"]]
    bad = []
    # The words reach the person only when said: heard in the speaking run, never in the muted one.
    if not any(o["human_id"] == 1 and o["cue"] == "keep_side" and o["side"] == "left"
               for o in heard["speaking"]):
        bad.append("speaking: the person did not hear that it should keep left")
    if heard["muted"]:
        bad.append(f"muted: a person heard a muted robot: {heard['muted']}")
    speaking = scenarios_of(tmp_path / "speaking" / "summary.json")[NAME]
    muted = scenarios_of(tmp_path / "muted" / "summary.json")[NAME]
    for label, s in (("speaking", speaking), ("muted", muted)):
        if s["final_state"] != "GOAL_REACHED" or s["contact"] is not None:
            bad.append(f"{label}: {s['final_state']}, contact {s['contact']} ({s['detail']})")
    hs, hm = speaking["humans"][0], muted["humans"][0]
    if not hm["docked"]:
        bad.append("muted: the robot did not dock (the words should be what avoids it)")
    if hs["docked"]:
        bad.append("speaking: the robot docked although the person kept to the other side")
    said = [e for e in hs["transcript"] if e["kind"] == "say" and e["round"] == 1]
    if not said or said[0]["act"] != "INFORM_DIRECTION" or said[0]["delivery"] != "said":
        bad.append(f"speaking: round 1 said {said}")
    elif not said[0]["lead_s"] > 0.0:
        bad.append(f"speaking: round 1's words end {said[0]['lead_s']} s before the crossing")
    if not any(e["kind"] == "say" and e["round"] == 1 and e["act"] == "INFORM_DIRECTION"
               and e["delivery"] == "muted" for e in hm["transcript"]):
        bad.append("muted: round 1 is not shown as not said (muted)")
    if any(e["kind"] == "say" and e["delivery"] != "muted" for e in hm["transcript"]):
        bad.append("muted: an utterance was said")
    cs, cm = hs["cm_interaction_m"], hm["cm_interaction_m"]
    print(f"CM speaking {cs:.3f} m, muted {cm:.3f} m; time to goal speaking "
          f"{speaking['robot_time_to_goal_s']} s, muted {muted['robot_time_to_goal_s']} s")
    if not cs > cm + 0.1:
        bad.append(f"CM speaking {cs} not above muted {cm} + 0.1 m")
    assert not bad
