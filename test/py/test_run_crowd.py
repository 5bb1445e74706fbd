"""Crowds: the crowd scenarios of config/scenarios run by scripts/run.sh with every daemon.
Whatever the people do, the robot reaches its goal without touching anyone, and what was said
passes the log's own dialogue checks (summary.json dialogue_checks, read from the recorded
messages, not from the dialogue manager's bookkeeping): nothing said to someone the robot is not
crossing, no contradictory words (a group told to part around the robot; someone told the robot
passes while it waits for another), no group told the same round twice. And what the crowd logic
is for is seen happening: the three walking abreast hear one plan, addressed to the three of
them; the people walking away ahead of the robot hear nothing; at the junction of junctions.pgm
the pair crossing the robot's path together is told once, as a pair, and the one turning away
ahead of the robot hears nothing."""

from conftest import run_sh, said_lines, scenarios_of

NAMES = ("crowd_2_open", "crowd_5_flows", "crowd_group_abreast", "crowd_standing_talk",
         "crowd_junction")


def test_crowds_are_addressed_told_once_per_group_never_contradicted(tmp_path, source_dir,
                                                                     port_base):
    run_sh(source_dir, tmp_path, *(source_dir / "config/scenarios" / f"{n}.yaml" for n in NAMES),
           port=port_base)
    for n in NAMES:
        print(f"{n}:\n{said_lines(tmp_path / n / 'transcript.txt')}")
    scen = scenarios_of(tmp_path / "summary.json")
    bad = []
    for name, s in sorted(scen.items()):
        c = s["dialogue_checks"]
        print(f"{name}: {s['final_state']}, min clearance {s['min_clearance_m']:.3f} m, said "
              f"{c['said']} ({c['addressed']} addressed), docks {s['docks']}")
        if s["final_state"] != "GOAL_REACHED" or s["contact"] is not None:
            bad.append(f"{name}: {s['final_state']}, contact {s['contact']} ({s['detail']})")
        for k in ("said_to_not_crossing", "contradictions", "told_twice"):
            bad += [f"{name}: {k}: {e}" for e in c[k]]
        # Several people in the scene: every said sentence says whom it is for.
        if c["addressed"] != c["said"]:
            bad.append(f"{name}: {c['said'] - c['addressed']} said sentences not addressed")
        said = [(h["id"], e) for h in s["humans"] for e in h["transcript"]
                if e["kind"] == "say" and e["delivery"] == "said"]
        if name == "crowd_5_flows":
            bad += [f"{name}: human {hid} walks away ahead of the robot and was told "
                    f"{e['text']!r}" for hid, e in said if hid in (4, 5)]
        if name == "crowd_junction":
            for hid, e in said:
                if hid == 5:
                    bad.append(f"{name}: human 5 walks away ahead of the robot and was told "
                               f"{e['text']!r}")
                if hid in (2, 3) and not e["text"].startswith("You two"):
                    bad.append(f"{name}: {e['text']!r} to human {hid} is not addressed to the "
                               "pair")
            for r in (1, 2):
                pair = [(hid, e) for hid, e in said if hid in (2, 3) and e["round"] == r]
                if len(pair) > 1:
                    bad.append(f"{name}: the pair heard round {r} {len(pair)} times: {pair}")
        if name == "crowd_group_abreast":
            round1 = [(hid, e) for hid, e in said if e["round"] == 1]
            if len(round1) > 1:
                bad.append(f"{name}: the group heard round 1 {len(round1)} times: {round1}")
            bad += [f"{name}: {e['text']!r} to human {hid} is not addressed to the group"
                    for hid, e in said if not e["text"].startswith(("You three", "You two"))]
    assert not bad
