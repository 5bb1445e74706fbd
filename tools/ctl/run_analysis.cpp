#include "run_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace coopnav::ctl {
namespace {

std::string codeName(const char* const* names, int first, int count, int code, const char* prefix) {
  if (code >= first && code < first + count) return names[code - first];
  return std::string(prefix) + std::to_string(code);
}

}  // namespace

std::string speechActName(std::int8_t act) {
  static const char* const kNames[] = {"INFORM_DIRECTION",
                                       "ASK_TO_MOVE",
                                       "INFORM_DOCK_IF_NEEDED",
                                       "REPEAT_DIRECTION",
                                       "ASK_TO_MOVE_MORE",
                                       "INFORM_DOCKING",
                                       "THANK",
                                       "INFORM_WIDER_PLACE",
                                       "INFORM_RETREAT",
                                       "INFORM_STOPPING",
                                       "INFORM_GOING_FIRST",
                                       "INFORM_RESUMING"};
  return codeName(kNames, utterance_t::ACT_INFORM_DIRECTION, 12, act, "ACT_");
}

std::string robotActionName(std::int8_t action) {
  static const char* const kNames[] = {"DOCK", "RESUME", "GO_FIRST", "SLOW"};
  return codeName(kNames, robot_action_t::ACTION_DOCK, 4, action, "ACTION_");
}

std::string recorderCommandName(std::int8_t command) {
  static const char* const kNames[] = {"START", "STOP", "RESET"};
  return codeName(kNames, path_assessor_control_t::COMMAND_START, 3, command, "COMMAND_");
}

std::string simStateName(std::int8_t state) {
  static const char* const kNames[] = {"RUNNING",    "GOAL_REACHED",        "COLLISION",
                                       "TIME_LIMIT", "PARTICIPANT_TIMEOUT", "ERROR",
                                       "STANDSTILL"};
  return codeName(kNames, sim_status_t::STATE_RUNNING, 7, state, "STATE_");
}

std::string crossingName(std::int8_t status) {
  static const char* const kNames[] = {"OK", "BEYOND_HORIZON", "BAD_BANDS", "NO_REFERENCE"};
  return codeName(kNames, situation_t::CROSSING_OK, 4, status, "CROSSING_");
}

std::string predicateName(std::int8_t pred) {
  static const char* const kNames[] = {"UNKNOWN", "FALSE", "TRUE"};
  return codeName(kNames, situation_t::PRED_UNKNOWN, 3, pred, "PRED_");
}

std::string directionName(std::int8_t dir) {
  static const char* const kNames[] = {"right", "undefined", "left"};
  return codeName(kNames, situation_t::DIR_RIGHT, 3, dir, "dir_");
}

std::string deliveryName(std::int8_t delivery) {
  static const char* const kNames[] = {"said", "muted", "too_late", "told_to_group", "contradicts"};
  return codeName(kNames, utterance_t::DELIVERY_SAID, 5, delivery, "delivery_");
}

bool wasSaid(std::int8_t delivery) {
  // Older logs (before deliveries) carry 0: said.
  return delivery != utterance_t::DELIVERY_MUTED && delivery != utterance_t::DELIVERY_TOO_LATE &&
         delivery != utterance_t::DELIVERY_TOLD_TO_GROUP &&
         delivery != utterance_t::DELIVERY_CONTRADICTS;
}

double utimeToS(std::int64_t utime) { return static_cast<double>(utime) * 1e-6; }

const HumanAnalysis* RunAnalysis::human(std::int32_t id) const {
  for (const auto& h : humans)
    if (h.id == id) return &h;
  return nullptr;
}

double RunAnalysis::tCrossAt(const RunLog& run, std::int32_t human_id, std::int64_t utime) const {
  const auto it = situation_at.find({human_id, utime});
  return it == situation_at.end() ? std::nan("") : run.situations[it->second].t_cross_s;
}

RunAnalysis analyseRun(const RunLog& run, const std::string& scenario_override) {
  RunAnalysis a;
  if (!run.sim_status.empty()) a.final_status = run.sim_status.size() - 1;
  a.scenario = scenario_override;
  if (a.scenario.empty() && a.final_status) a.scenario = run.sim_status[*a.final_status].scenario;

  std::set<std::int32_t> ids;
  for (const auto& s : run.agent_states)
    for (const auto& h : s.humans) ids.insert(h.id);
  for (const auto& s : run.situations) ids.insert(s.human_id);
  for (const auto& p : run.assessments) ids.insert(p.human_id);
  for (const auto& u : run.utterances) ids.insert(u.human_id);
  std::map<std::int32_t, HumanAnalysis> by_id;
  for (const auto id : ids) by_id[id].id = id;

  for (std::size_t i = 0; i < run.situations.size(); ++i) {
    const auto& s = run.situations[i];
    a.situation_at.emplace(std::make_pair(s.human_id, s.utime), i);
  }

  // Interaction CA: each message's window is the newest part of the interaction.
  for (std::size_t i = 0; i < run.assessments.size(); ++i) {
    const auto& p = run.assessments[i];
    HumanAnalysis& h = by_id[p.human_id];
    h.last_assessment = i;
    const std::int64_t window = p.window_samples;
    const std::int64_t prefix = std::int64_t{p.interaction_samples} - window;
    const bool whole_window = p.num_samples == p.window_samples && window >= 0;
    if (!whole_window || prefix < 0) {
      h.interaction_ca_complete = false;
      continue;
    }
    if (prefix == 0) {
      h.interaction_ca_m = p.ca_m;
      h.window_starts = {0};
      h.interaction_ca_complete = true;
    } else if (h.interaction_ca_complete &&
               static_cast<std::size_t>(prefix) <= h.interaction_ca_m.size()) {
      h.interaction_ca_m.resize(static_cast<std::size_t>(prefix));
      h.interaction_ca_m.insert(h.interaction_ca_m.end(), p.ca_m.begin(), p.ca_m.end());
      const auto start = static_cast<std::size_t>(prefix);
      while (!h.window_starts.empty() && h.window_starts.back() > start) h.window_starts.pop_back();
      if (h.window_starts.empty() || h.window_starts.back() != start)
        h.window_starts.push_back(start);
    } else {
      h.interaction_ca_complete = false;
    }
  }

  for (const auto& c : run.controls) {
    if (c.command == path_assessor_control_t::COMMAND_START && by_id.count(c.human_id))
      by_id[c.human_id].recorder_start_s = utimeToS(c.utime);
  }
  for (const auto& act : run.actions) {
    if (act.action == robot_action_t::ACTION_DOCK && by_id.count(act.human_id))
      by_id[act.human_id].docked = true;
  }

  // Crossing points at the first round: the first utterance's step, else t_CROSS <= 7 s.
  for (const auto& u : run.utterances) {
    HumanAnalysis& h = by_id[u.human_id];
    if (h.first_round_situation) continue;
    const auto it = a.situation_at.find({u.human_id, u.utime});
    if (it != a.situation_at.end()) h.first_round_situation = it->second;
  }
  for (std::size_t i = 0; i < run.situations.size(); ++i) {
    const auto& s = run.situations[i];
    HumanAnalysis& h = by_id[s.human_id];
    if (h.first_round_situation) continue;
    if (std::isfinite(s.t_cross_s) && s.t_cross_s <= kRound1TCross_s && std::isfinite(s.cp_h_x_m) &&
        std::isfinite(s.cp_r_x_m))
      h.first_round_situation = i;
  }

  for (auto& [id, h] : by_id) a.humans.push_back(std::move(h));
  return a;
}

}  // namespace coopnav::ctl
