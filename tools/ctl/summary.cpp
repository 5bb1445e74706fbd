#include "summary.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "action_words.hpp"
#include "coopnav/assessment/path_assessment.hpp"
#include "json.hpp"
#include "progress_metrics.hpp"
#include "transcript.hpp"

namespace coopnav::ctl {
namespace {

Json tristateJson(std::int8_t pred) {
  if (pred == situation_t::PRED_TRUE) return true;
  if (pred == situation_t::PRED_FALSE) return false;
  return nullptr;
}

std::string recordingName(std::int8_t rec) {
  switch (rec) {
    case path_assessment_t::REC_IDLE:
      return "IDLE";
    case path_assessment_t::REC_RECORDING:
      return "RECORDING";
    case path_assessment_t::REC_STOPPED:
      return "STOPPED";
    default:
      return "REC_" + std::to_string(rec);
  }
}

Json cmByGamma(const std::vector<double>& ca_m) {
  Json o = Json::object();
  for (const double gamma : kSummaryGammas) {
    char key[16];
    std::snprintf(key, sizeof key, "%.2f", gamma);
    o[key] = numberOrNull(assessment::discountedMean(ca_m, gamma));
  }
  return o;
}

Json point(double x, double y) { return Json::array({numberOrNull(x), numberOrNull(y)}); }

// [m] Minimum robot-human clearance (centre distance minus radii) over the logged states; NaN
// when no state has both.
double minClearanceFromStates(const RunLog& run) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : run.agent_states) {
    for (const auto& h : s.humans) {
      const double d =
          std::hypot(h.x_m - s.robot.x_m, h.y_m - s.robot.y_m) - h.radius_m - s.robot.radius_m;
      if (std::isfinite(d)) best = std::min(best, d);
    }
  }
  return std::isfinite(best) ? best : std::nan("");
}

// The first robot-human contact of the final sim status: null when there was none.
Json contactJson(const sim_status_t& st) {
  if (st.contact == sim_status_t::CONTACT_NONE) return nullptr;
  Json c = Json::object();
  c["human_id"] = std::int64_t{st.contact_human_id};
  c["t_s"] = numberOrNull(st.contact_t_s);
  c["robot_at_fault"] = st.contact == sim_status_t::CONTACT_ROBOT_AT_FAULT;
  c["robot_speed_m_s"] = numberOrNull(st.contact_robot_speed_m_s);
  return c;
}

/// Goal inference for human id (null when the band source inferred none, e.g. goals given): the
/// most likely candidate at the first round (the last estimate at or before it), and the truth
/// as for real walkers: the candidate whose centre is nearest to where the human was last seen.
Json goalInferenceJson(const RunLog& run, std::int32_t id,
                       std::optional<std::int64_t> round1_utime) {
  const goal_estimate_t* at_round1 = nullptr;
  const goal_estimates_t* list = nullptr;
  bool any = false;
  for (const auto& m : run.goal_estimates) {
    for (const auto& e : m.humans) {
      if (e.agent_id != id) continue;
      any = true;
      if (round1_utime && m.utime <= *round1_utime) {
        at_round1 = &e;
        list = &m;
      }
    }
  }
  if (!any) return nullptr;
  std::optional<Eigen::Vector2d> last;
  for (const auto& st : run.agent_states)
    for (const auto& a : st.humans)
      if (a.id == id) last = Eigen::Vector2d(a.x_m, a.y_m);
  Json g = Json::object();
  g["last_seen_m"] = last ? point(last->x(), last->y()) : Json();
  g["at_round1"] = nullptr;
  g["p_at_round1"] = nullptr;
  g["truth"] = nullptr;
  g["correct"] = nullptr;
  if (list == nullptr) return g;
  g["candidates"] = list->num_goals;
  // most_likely comes from the bus (any peer can publish it, the recorder keeps it): an index
  // outside this estimate's own probabilities or the list's goals names no candidate.
  const bool index_valid =
      at_round1->most_likely >= 0 &&
      static_cast<std::size_t>(at_round1->most_likely) < at_round1->probability.size() &&
      at_round1->most_likely < list->num_goals;
  if (index_valid) {
    g["at_round1"] = at_round1->most_likely;
    g["p_at_round1"] =
        numberOrNull(at_round1->probability[static_cast<std::size_t>(at_round1->most_likely)]);
  }
  if (!last || list->num_goals <= 0 ||
      static_cast<std::size_t>(list->num_goals) > list->goal_x_m.size() ||
      static_cast<std::size_t>(list->num_goals) > list->goal_y_m.size())
    return g;
  int truth = 0;
  for (int k = 1; k < list->num_goals; ++k) {
    const auto d = [&](int i) {
      return std::hypot(list->goal_x_m[static_cast<std::size_t>(i)] - last->x(),
                        list->goal_y_m[static_cast<std::size_t>(i)] - last->y());
    };
    if (d(k) < d(truth)) truth = k;
  }
  g["truth"] = truth;
  g["correct"] = index_valid && at_round1->most_likely == truth;
  return g;
}

/// [s] p_contributing over time is kept at most this often: its model reads velocities over 0.8 s
/// spans, so a finer series repeats itself and a long run's summary would grow with the tracker's
/// rate.
constexpr double kPContributingPeriodS = 0.5;

/// The forecast p_contributing of human `id` over time: `[t_s, p]` (p null while unknown) at the
/// first assessment and then every kPContributingPeriodS of message time, and at the last one.
Json pContributingSeries(const RunLog& run, std::int32_t id) {
  Json series = Json::array();
  std::optional<double> last_kept_s;
  const path_assessment_t* last = nullptr;
  for (const auto& a : run.assessments) {
    if (a.human_id != id) continue;
    last = &a;
    const double t_s = utimeToS(a.utime);
    if (last_kept_s && t_s < *last_kept_s + kPContributingPeriodS) continue;
    last_kept_s = t_s;
    series.push_back(Json::array({numberOrNull(t_s), numberOrNull(a.p_contributing)}));
  }
  if (last && last_kept_s && utimeToS(last->utime) > *last_kept_s)
    series.push_back(
        Json::array({numberOrNull(utimeToS(last->utime)), numberOrNull(last->p_contributing)}));
  return series;
}

/// p_contributing of human `id` in its latest assessment at or before `utime` (NaN: none).
double pContributingAt(const RunLog& run, std::int32_t id, std::int64_t utime) {
  double p = std::numeric_limits<double>::quiet_NaN();
  for (const auto& a : run.assessments)
    if (a.human_id == id && a.utime <= utime) p = a.p_contributing;
  return p;
}

Json humanEntry(const RunLog& run, const HumanAnalysis& h,
                const std::vector<TranscriptEntry>& transcript) {
  Json o = Json::object();
  o["id"] = std::int64_t{h.id};
  const path_assessment_t* p = h.last_assessment ? &run.assessments[*h.last_assessment] : nullptr;
  if (p) {
    o["cm_window_m"] = numberOrNull(p->cm_m);
    o["window_samples"] = std::int64_t{p->window_samples};
    o["is_contributing"] = tristateJson(p->is_contributing);
    o["cm_interaction_m"] = numberOrNull(p->cm_interaction_m);
    o["interaction_samples"] = std::int64_t{p->interaction_samples};
    o["is_contributing_interaction"] = tristateJson(p->is_contributing_interaction);
    o["gamma"] = numberOrNull(p->gamma);
    o["tau_m"] = numberOrNull(p->tau_m);
    o["tau_mode"] = p->tau_mode == path_assessment_t::TAU_ROOM ? "room" : "fixed";
    o["tau_fixed_m"] = numberOrNull(p->tau_fixed_m);
    o["room_m"] = numberOrNull(p->room_m);  // null: unknown, or unbounded (+inf)
    o["tau_room_m"] = numberOrNull(p->tau_room_m);
    o["profile"] = p->profile;
    o["side_rule"] =
        p->side_rule == path_assessment_t::SIDE_RULE_HUMAN ? "human_side" : "path_side";
    o["recording"] = recordingName(p->recording);
    o["cm_by_gamma"] = cmByGamma(p->ca_m);
    o["cm_by_gamma_complete"] = p->num_samples == p->window_samples;
    o["p_contributing"] = numberOrNull(p->p_contributing);
  } else {
    for (const char* k : {"cm_window_m", "window_samples", "is_contributing", "cm_interaction_m",
                          "interaction_samples", "is_contributing_interaction", "gamma", "tau_m",
                          "tau_mode", "tau_fixed_m", "room_m", "tau_room_m", "profile", "side_rule",
                          "recording", "cm_by_gamma", "p_contributing"})
      o[k] = nullptr;
    o["cm_by_gamma_complete"] = false;
  }
  o["p_contributing_over_time"] = pContributingSeries(run, h.id);
  o["cm_interaction_by_gamma"] = h.interaction_ca_complete ? cmByGamma(h.interaction_ca_m) : Json();
  o["interaction_ca_complete"] = h.interaction_ca_complete;
  // The CA itself, so that a γ sweep across scenarios (paper Fig. 7) needs only this file.
  const std::vector<double>* ca = h.interaction_ca_complete ? &h.interaction_ca_m
                                  : p                       ? &p->ca_m
                                                            : nullptr;
  o["ca_kind"] = ca ? Json(h.interaction_ca_complete ? "interaction" : "window") : Json();
  Json ca_json = Json::array();
  if (ca)
    for (const double v : *ca) ca_json.push_back(numberOrNull(v));
  o["ca_m"] = std::move(ca_json);
  o["recorder_start_s"] = numberOrNull(h.recorder_start_s);
  o["docked"] = h.docked;
  bool thanked = false;
  for (const auto& u : run.utterances)
    thanked = thanked ||
              (u.human_id == h.id && u.speech_act == utterance_t::ACT_THANK && wasSaid(u.delivery));
  o["thanked"] = thanked;

  if (h.first_round_situation) {
    const auto& s = run.situations[*h.first_round_situation];
    Json r = Json::object();
    r["t_s"] = numberOrNull(utimeToS(s.utime));
    r["t_cross_s"] = numberOrNull(s.t_cross_s);
    r["cp_h_m"] = point(s.cp_h_x_m, s.cp_h_y_m);
    r["cp_r_m"] = point(s.cp_r_x_m, s.cp_r_y_m);
    r["dir"] = directionName(s.dir);
    r["d_h_m"] = numberOrNull(s.d_h_m);
    r["human_needs_to_contribute"] = tristateJson(s.human_needs_to_contribute);
    r["human_is_constrained"] = tristateJson(s.human_is_constrained);
    r["robot_is_constrained"] = tristateJson(s.robot_is_constrained);
    o["first_round"] = std::move(r);
  } else {
    o["first_round"] = nullptr;
  }
  o["goal_inference"] = goalInferenceJson(
      run, h.id,
      h.first_round_situation
          ? std::optional<std::int64_t>(run.situations[*h.first_round_situation].utime)
          : std::nullopt);

  Json entries = Json::array();
  using Kind = TranscriptEntry::Kind;
  for (const auto& e : transcript) {
    if (e.human_id != h.id) continue;
    if (e.kind != Kind::kSay && e.kind != Kind::kAction && e.kind != Kind::kRecorder) continue;
    Json j = Json::object();
    j["t_s"] = numberOrNull(utimeToS(e.utime));
    j["t_cross_s"] = numberOrNull(e.t_cross_s);
    if (e.kind == Kind::kSay) {
      j["kind"] = "say";
      j["act"] = e.what;
      j["text"] = e.text;
      j["round"] = std::int64_t{e.round};
      // The forecast the decision of this round could read (the latest assessment before it).
      j["p_contributing"] = numberOrNull(pContributingAt(run, h.id, e.utime));
      j["direction"] = e.direction;
      j["delivery"] = e.delivery;
      j["speech_start_s"] = numberOrNull(e.speech_start_s);
      j["speech_duration_s"] = numberOrNull(e.speech_duration_s);
      // How long before t_CROSS the words end (< 0: after it); what a listener has left to act.
      j["lead_s"] = numberOrNull(e.t_cross_s - (e.speech_start_s + e.speech_duration_s));
    } else {
      j["kind"] = e.kind == Kind::kAction ? "action" : "recorder";
      j[e.kind == Kind::kAction ? "action" : "command"] = e.what;
      j["reason"] = e.text;
      // Acted on a fallback, not on the flowchart (the precautionary dock): the decision's
      // branch, which the reason carries, says "degraded:" (dialogue::RoundOutcome::degraded).
      j["degraded"] = e.text.find("degraded:") != std::string::npos;
    }
    entries.push_back(std::move(j));
  }
  o["transcript"] = std::move(entries);
  return o;
}

/// The side a said utterance tells its human the robot passes on (DIR_*), 0 when it says none.
int robotSideOf(const utterance_t& u) {
  switch (u.speech_act) {
    case utterance_t::ACT_INFORM_DIRECTION:
    case utterance_t::ACT_REPEAT_DIRECTION:
      return u.direction;
    case utterance_t::ACT_ASK_TO_MOVE:
    case utterance_t::ACT_ASK_TO_MOVE_MORE:
      return -u.direction;
    default:
      return 0;
  }
}

/// Checks of what was said to several people, read from the log alone (not from the dialogue
/// manager's own bookkeeping): words said to someone the robot is not crossing (no crossing ahead
/// in that human's latest situation), words that contradict each other (a group told two robot
/// sides in one round; someone told the robot passes while it holds a dock), and a group told the
/// same round twice.
Json dialogueChecks(const RunLog& run) {
  Json said_to_not_crossing = Json::array(), contradictions = Json::array(),
       told_twice = Json::array();
  std::int64_t said = 0, addressed = 0;
  auto label = [](const utterance_t& u) {
    return fixed(utimeToS(u.utime), 2) + " s human " + std::to_string(u.human_id) + " " +
           speechActName(u.speech_act) + " round " + std::to_string(u.round);
  };
  std::vector<const utterance_t*> earlier;
  for (const auto& u : run.utterances) {
    if (!wasSaid(u.delivery)) continue;
    ++said;
    if (!u.group_ids.empty() || u.text.rfind("You ", 0) == 0 || u.text.rfind("All of you", 0) == 0)
      ++addressed;
    // The words that end a stand-off are said to a person standing within reach and not yet
    // crossed (lib/dialogue/stand_off.hpp), whose closest approach is "now" (t_CROSS 0) because
    // nobody moves: they are not words to someone the robot is not crossing.
    // So are the words of the robot making room to end a stand-off (a dock, a wider place, a
    // retreat, a stop), said while the person's latest DOCK was decided on the stand-off (its
    // reason, as the dialogue manager writes it, "round 2: stand-off: ..."): a later stand-off
    // makes room again. Each answers a stand-off of its own: none is a group told twice.
    const bool making_room = u.speech_act == utterance_t::ACT_INFORM_DOCKING ||
                             u.speech_act == utterance_t::ACT_INFORM_WIDER_PLACE ||
                             u.speech_act == utterance_t::ACT_INFORM_RETREAT ||
                             u.speech_act == utterance_t::ACT_INFORM_STOPPING;
    const robot_action_t* last_action = nullptr;
    if (making_room)
      for (const auto& a : run.actions)
        if (a.human_id == u.human_id && a.utime <= u.utime) last_action = &a;
    const bool stand_off_dock = last_action && last_action->action == robot_action_t::ACTION_DOCK &&
                                last_action->reason.find("stand-off:") != std::string::npos;
    const bool ends_stand_off = u.speech_act == utterance_t::ACT_INFORM_GOING_FIRST ||
                                u.speech_act == utterance_t::ACT_INFORM_RESUMING || stand_off_dock;
    // The words announcing a pass of a person ahead walking the robot's way (the GO_FIRST for
    // them that follows is decided "overtake: ...", lib/dialogue/overtake_words.hpp): the robot
    // is about to cross them, from behind, where the flowchart's crossing of two bands
    // converging is beyond its horizon while the robot follows at their pace.
    bool announces_pass = false;
    if (u.speech_act == utterance_t::ACT_INFORM_DIRECTION)
      for (const auto& a : run.actions)
        if (a.human_id == u.human_id && a.utime >= u.utime &&
            a.action == robot_action_t::ACTION_GO_FIRST &&
            a.reason.find("overtake:") != std::string::npos) {
          announces_pass = true;
          break;
        }
    if ((u.round == 1 || u.round == 2) && !ends_stand_off && !announces_pass) {
      const situation_t* latest = nullptr;
      for (const auto& sit : run.situations)
        if (sit.human_id == u.human_id && sit.utime <= u.utime &&
            (!latest || sit.utime >= latest->utime))
          latest = &sit;
      if (!latest || latest->crossing_status != situation_t::CROSSING_OK ||
          !(latest->t_cross_s > 0.0))
        said_to_not_crossing.push_back(label(u));
    }
    // Docks open at this utterance (a dock and no resume for that human before it).
    const int side = robotSideOf(u);
    if (side != 0) {
      std::map<std::int32_t, bool> open;
      for (const auto& a : run.actions)
        if (a.utime <= u.utime) open[a.human_id] = a.action == robot_action_t::ACTION_DOCK;
      for (const auto& [id, is_open] : open)
        if (is_open) {
          contradictions.push_back(label(u) + ": says the robot passes while it waits for human " +
                                   std::to_string(id));
          break;
        }
    }
    for (const utterance_t* e : earlier) {
      if (e->round != u.round || ends_stand_off) continue;
      const auto& g = e->group_ids;
      const bool together =
          std::find(g.begin(), g.end(), u.human_id) != g.end() ||
          std::find(u.group_ids.begin(), u.group_ids.end(), e->human_id) != u.group_ids.end();
      if (!together) continue;
      const int other = robotSideOf(*e);
      if (side != 0 && other != 0 && side != other)
        contradictions.push_back(label(u) + ": its group was told the other side (" + label(*e) +
                                 ")");
      else if (u.speech_act == e->speech_act || (side != 0 && side == other))
        told_twice.push_back(label(u) + " (" + label(*e) + ")");
    }
    earlier.push_back(&u);
  }
  Json j = Json::object();
  j["said"] = said;
  j["addressed"] = addressed;
  j["said_to_not_crossing"] = std::move(said_to_not_crossing);
  j["contradictions"] = std::move(contradictions);
  j["told_twice"] = std::move(told_twice);
  const ActionWordsCheck action_words = checkActionWords(run);
  j["action_contradicts_words"] = action_words.contradictions;
  j["action_words_too_late"] = action_words.unsaid_too_late;
  return j;
}

}  // namespace

RobotBehaviourCounts countRobotBehaviour(const RunLog& run) {
  RobotBehaviourCounts n;
  std::int8_t previous = velocity_command_t::MODE_IDLE;
  for (const auto& c : run.commands) {
    const bool first = n.commands++ == 0;
    if (c.mode == velocity_command_t::MODE_DOCKING &&
        (first || previous != velocity_command_t::MODE_DOCKING))
      ++n.docks;
    if (c.mode == velocity_command_t::MODE_RETREATING &&
        (first || previous != velocity_command_t::MODE_RETREATING))
      ++n.retreats;
    if (c.guard != velocity_command_t::GUARD_NONE) ++n.guard_steps;
    previous = c.mode;
  }
  return n;
}

namespace {

// What a fault run is judged by (scripts/coopnav faults, multihost): the restarts the step acks
// announced, the last step each participant acknowledged, the daemons that reported themselves
// degraded (wall-clock status, unique name and detail),
// and the situations of a crossing whose obstacle distances were unknown (d_OH or d_OR NaN
// although the crossing was found: the distance server did not answer in time, or at all, or
// answered that the point is off the map).
Json faultsJson(const RunLog& run) {
  Json restarts = Json::array();
  for (const auto& a : run.restarts) {
    Json r = Json::object();
    r["participant"] = a.participant;
    r["t_s"] = numberOrNull(utimeToS(a.utime));
    r["step"] = a.restart_step;
    r["recovered"] = a.restart == step_ack_t::RESTART_RECOVERED;
    r["note"] = a.restart_note;
    restarts.push_back(std::move(r));
  }
  Json degraded = Json::array();
  std::set<std::pair<std::string, std::string>> seen;
  for (const auto& st : run.daemon_status) {
    if (st.state != daemon_status_t::STATE_DEGRADED || !seen.insert({st.name, st.detail}).second)
      continue;
    Json d = Json::object();
    d["name"] = st.name;
    d["detail"] = st.detail;
    degraded.push_back(std::move(d));
  }
  std::int64_t crossings = 0;
  std::int64_t distance_unknown = 0;
  for (const auto& sit : run.situations) {
    if (sit.crossing_status != situation_t::CROSSING_OK) continue;
    ++crossings;
    if (std::isnan(sit.d_oh_m) || std::isnan(sit.d_or_m)) ++distance_unknown;
  }
  // Who answered the lockstep how far (logic steps, deterministic): a participant behind the
  // others stopped answering, and a daemon that acknowledged later steps than a peer it waits for
  // ran those steps without it (what the multihost drop-off is judged by).
  Json last_acked = Json::object();
  for (const auto& [participant, step] : run.last_acked_step) last_acked[participant] = step;
  Json f = Json::object();
  f["restarts"] = std::move(restarts);
  f["degraded_daemons"] = std::move(degraded);
  f["last_acked_step"] = std::move(last_acked);
  f["crossing_situations"] = crossings;
  f["crossing_distance_unknown"] = distance_unknown;
  return f;
}

}  // namespace

Json summarizeRun(const RunLog& run, const RunAnalysis& analysis, const std::string& log_name) {
  TranscriptOptions topt;
  topt.include_unknown = false;
  topt.include_final_cm = false;
  topt.include_sim_status = false;
  const auto transcript = buildTranscript(run, analysis, topt);

  Json s = Json::object();
  s["scenario"] = analysis.scenario;
  s["log"] = log_name;
  const sim_status_t* st =
      analysis.final_status ? &run.sim_status[*analysis.final_status] : nullptr;
  if (st) {
    s["final_state"] = simStateName(st->state);
    s["collision"] = st->state == sim_status_t::STATE_COLLISION;
    s["min_clearance_m"] = numberOrNull(st->min_clearance_m);
    s["robot_time_to_goal_s"] = numberOrNull(st->robot_time_to_goal_s);
    s["sim_time_s"] = numberOrNull(utimeToS(st->utime));
    s["last_step"] = st->step;
    s["detail"] = st->detail;
    s["outcome"] = simStateName(st->state);
    s["min_clearance_t_s"] = numberOrNull(st->min_clearance_t_s);
    s["contact"] = contactJson(*st);
  } else {
    for (const char* k :
         {"final_state", "collision", "min_clearance_m", "robot_time_to_goal_s", "sim_time_s",
          "last_step", "detail", "outcome", "min_clearance_t_s", "contact"})
      s[k] = nullptr;
  }
  s["min_clearance_states_m"] = numberOrNull(minClearanceFromStates(run));
  bool docked = false;
  for (const auto& h : analysis.humans) docked = docked || h.docked;
  s["docked"] = docked;
  const RobotBehaviourCounts robot = countRobotBehaviour(run);
  s["docks"] = robot.docks;
  s["retreats"] = robot.retreats;
  s["guard_steps"] = robot.guard_steps;
  const ProgressMetrics progress = progressMetrics(run);
  s["stalled_s"] = progress.stalled_s;
  s["max_mutual_wait_s"] = progress.max_mutual_wait_s;
  s["max_mutual_wait_start_s"] = numberOrNull(progress.max_mutual_wait_start_s);
  s["max_mutual_wait_human_id"] = progress.max_mutual_wait_human >= 0
                                      ? Json(std::int64_t{progress.max_mutual_wait_human})
                                      : Json();

  Json humans = Json::array();
  for (const auto& h : analysis.humans) humans.push_back(humanEntry(run, h, transcript));
  s["humans"] = std::move(humans);
  s["dialogue_checks"] = dialogueChecks(run);
  s["faults"] = faultsJson(run);

  const auto& c = run.counts;
  Json counts = Json::object();
  counts["events"] = c.events;
  counts["decoded"] = c.decoded;
  counts["not_needed"] = c.not_needed;
  counts["undecodable"] = c.undecodable;
  counts["unknown_channel"] = c.unknown_channel;
  counts["bad_headers"] = c.bad_headers;
  counts["skipped_bytes"] = c.skipped_bytes;
  counts["truncated"] = c.truncated;
  s["log_counts"] = std::move(counts);
  return s;
}

Json summaryDocument(const std::vector<Json>& scenario_entries) {
  Json doc = Json::object();
  doc["format"] = kSummaryFormat;
  doc["scenarios"] = Json::array_t(scenario_entries.begin(), scenario_entries.end());
  return doc;
}

Json mergeSummaries(const std::vector<Json>& documents) {
  std::vector<Json> merged;
  for (const auto& doc : documents) {
    const Json* list = member(doc, "scenarios");
    if (!list || !list->is_array())
      throw std::runtime_error("not a coopnav summary (no \"scenarios\" array)");
    for (const auto& entry : *list) {
      const std::string key = stringValue(member(entry, "scenario"));
      auto it = std::find_if(merged.begin(), merged.end(), [&](const Json& m) {
        return stringValue(member(m, "scenario")) == key;
      });
      if (it != merged.end())
        *it = entry;
      else
        merged.push_back(entry);
    }
  }
  return summaryDocument(merged);
}

Json readSummaryFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  try {
    return parseJson(ss.str());
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

void writeTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path);
}

double paperTableCm(const std::string& scenario) {
  // Paper Table I: rows Open / Narrow, columns Minimally Contributing / Facilitating.
  static const std::pair<const char*, double> kTable[] = {{"open_minimal", 0.15},
                                                          {"open_facilitating", 0.94},
                                                          {"narrow_minimal", 0.05},
                                                          {"narrow_facilitating", 0.49}};
  for (const auto& [name, cm] : kTable)
    if (scenario.rfind(name, 0) == 0) return cm;
  return std::nan("");
}

std::string formatCmTable(const Json& summary) {
  const Json* list = member(summary, "scenarios");
  if (!list || !list->is_array())
    throw std::runtime_error("not a coopnav summary (no \"scenarios\" array)");

  // Table I order first (open then narrow; facilitating then minimal).
  static const char* const kOrder[] = {"open_facilitating", "open_minimal", "narrow_facilitating",
                                       "narrow_minimal"};
  std::vector<const Json*> rows;
  for (const char* name : kOrder)
    for (const auto& e : *list)
      if (const Json* n = member(e, "scenario"); n && stringValue(n).rfind(name, 0) == 0)
        rows.push_back(&e);
  for (const auto& e : *list)
    if (std::find(rows.begin(), rows.end(), &e) == rows.end()) rows.push_back(&e);

  auto boolText = [](const Json* j) {
    if (!j || j->is_null()) return std::string("-");
    return std::string(boolValue(j) ? "yes" : "no");
  };
  auto predText = [](const Json* j) {
    if (!j || j->is_null()) return std::string("UNKNOWN");
    return std::string(boolValue(j) ? "TRUE" : "FALSE");
  };
  auto num = [](const Json* j) { return fixed(numberValue(j), 2); };

  // What ran, from the path assessments themselves (never assumed): one line per distinct
  // setting, so a table of mixed runs says so.
  std::vector<std::string> settings;
  for (const Json* e : rows)
    for (const auto& h : elements(member(*e, "humans"))) {
      const Json* gamma = member(h, "gamma");
      if (!gamma || gamma->is_null()) continue;
      const Json* tau = member(h, "tau_m");
      const Json* tau_mode = member(h, "tau_mode");
      const Json* profile = member(h, "profile");
      std::string line = "gamma " + fixed(numberValue(gamma), 2) + ", tau " +
                         (tau && !tau->is_null() ? fixed(numberValue(tau), 2) : "-") + " m";
      if (tau_mode && tau_mode->is_string()) line += " (" + stringValue(tau_mode) + ")";
      line +=
          ", profile " + (profile && profile->is_string() ? printable(stringValue(profile)) : "-");
      if (std::find(settings.begin(), settings.end(), line) == settings.end())
        settings.push_back(line);
    }
  std::string ran = settings.empty() ? std::string("no path assessment") : settings.front();
  for (std::size_t i = 1; i < settings.size(); ++i) ran += "; " + settings[i];
  std::string out =
      "CM [m]: ours = interaction CM (round 1 to crossing, no reset), as Table I reports it;\n"
      "window = CM since the last reset (round 2 decides on it). Paper = Table I (gamma 0.98, "
      "tau 0.40 m).\nRan with: " +
      ran + ".\n";
  char buf[512];
  std::snprintf(buf, sizeof buf, "%-24s %5s %8s %9s %9s %-15s %-6s %-9s %s\n", "scenario", "human",
                "CM ours", "CM paper", "CM window", "IsContributing", "docked", "collision",
                "final state");
  out += buf;
  for (const Json* e : rows) {
    const std::string raw_name = stringValue(member(*e, "scenario"));
    const std::string name = printable(raw_name);
    const Json* humans = member(*e, "humans");
    const std::string paper = fixed(paperTableCm(raw_name), 2);
    const Json* final_state = member(*e, "final_state");
    const std::string state =
        final_state && !final_state->is_null() ? printable(stringValue(final_state)) : "-";
    if (elements(humans).empty()) {
      std::snprintf(buf, sizeof buf, "%-24s %5s %8s %9s %9s %-15s %-6s %-9s %s\n", name.c_str(),
                    "-", "-", paper.c_str(), "-", "-", boolText(member(*e, "docked")).c_str(),
                    boolText(member(*e, "collision")).c_str(), state.c_str());
      out += buf;
      continue;
    }
    for (const auto& h : elements(humans)) {
      const Json* id = member(h, "id");
      const std::string id_text = id ? jsonNumber(numberValue(id)) : "-";
      std::snprintf(buf, sizeof buf, "%-24s %5s %8s %9s %9s %-15s %-6s %-9s %s\n", name.c_str(),
                    id_text.c_str(), num(member(h, "cm_interaction_m")).c_str(), paper.c_str(),
                    num(member(h, "cm_window_m")).c_str(),
                    predText(member(h, "is_contributing_interaction")).c_str(),
                    boolText(member(h, "docked")).c_str(),
                    boolText(member(*e, "collision")).c_str(), state.c_str());
      out += buf;
    }
  }
  return out;
}

}  // namespace coopnav::ctl
