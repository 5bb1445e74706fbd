#include "transcript.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "json.hpp"

namespace coopnav::ctl {
namespace {

// Within one time stamp: why a situation was unknown, then what the dialogue manager did (in its
// publishing order), as the pipeline runs (lockstep: situation before decision).
int rank(TranscriptEntry::Kind k) { return k == TranscriptEntry::Kind::kUnknown ? 0 : 1; }

std::string prefix(std::int64_t utime, std::int32_t human_id, double t_cross_s) {
  std::string s = "t=" + fixed(utimeToS(utime), 2) + "s  human " + std::to_string(human_id) +
                  "  t_cross=" + fixed(t_cross_s, 2);
  if (std::isfinite(t_cross_s)) s += "s";
  return s;
}

std::string why(const std::string& reason) {
  return reason.empty() ? std::string() : " (why: " + printable(reason) + ")";
}

}  // namespace

std::string fixed(double v, int decimals) {
  if (std::isnan(v)) return "-";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  // "-0.00" and "0.00" are the same reading.
  std::string s = buf;
  if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

// The kind of an unknown reason: its text with numbers blanked, so "horizon (10.6 s)" and
// "horizon (9.9 s)" count as one reason and the transcript names it once.
static std::string reasonKind(const std::string& reason) {
  std::string out;
  bool in_number = false;
  for (char c : reason) {
    const bool digit = (c >= '0' && c <= '9') || (in_number && c == '.');
    if (digit) {
      if (!in_number) out += '#';
      in_number = true;
    } else {
      in_number = false;
      out += c;
    }
  }
  return out;
}

std::vector<TranscriptEntry> buildTranscript(const RunLog& run, const RunAnalysis& analysis,
                                             const TranscriptOptions& options) {
  using Kind = TranscriptEntry::Kind;
  std::vector<TranscriptEntry> events;

  // First occurrence of each unknown reason per human, with how often it occurred.
  std::map<std::pair<std::int32_t, std::string>, std::size_t> unknown_first;
  std::map<std::pair<std::int32_t, std::string>, std::int64_t> unknown_count;
  std::map<std::int32_t, int> reasons_per_human;
  if (options.include_unknown) {
    for (const auto& s : run.situations)
      if (!s.reason.empty()) ++unknown_count[{s.human_id, reasonKind(s.reason)}];
  }

  std::int64_t last_step_utime = 0;
  std::set<std::pair<std::string, std::string>> degraded_seen;
  for (const auto& ref : run.order) {
    TranscriptEntry e;
    switch (ref.kind) {
      case RunLog::Kind::kAgentStates:
        last_step_utime = run.agent_states[ref.index].utime;
        continue;
      case RunLog::Kind::kGoalEstimates:
        continue;
      case RunLog::Kind::kDaemonStatus: {
        const auto& st = run.daemon_status[ref.index];
        if (!options.include_daemon_status || st.state != daemon_status_t::STATE_DEGRADED) continue;
        if (!degraded_seen.insert({st.name, st.detail}).second) continue;
        e.kind = Kind::kDaemonDegraded;
        e.utime = last_step_utime;
        e.t_cross_s = std::nan("");
        e.what = st.name;
        e.text = st.detail;
        e.line = "t~" + fixed(utimeToS(e.utime), 2) + "s  DAEMON " + printable(st.name) +
                 " DEGRADED " + jsonQuote(st.detail) +
                 " (wall-clock status; time of the last step logged)";
        break;
      }
      case RunLog::Kind::kRestart: {
        // Said in the transcript, never silent: a restart whose state was lost degrades what
        // follows (docs/lockstep.md "Loss and restarts").
        const auto& a = run.restarts[ref.index];
        e.kind = Kind::kRestart;
        e.utime = a.utime;
        e.t_cross_s = std::nan("");
        e.what = a.participant;
        e.text = a.restart_note;
        e.line = "t=" + fixed(utimeToS(a.utime), 2) + "s  " +
                 (a.restart == step_ack_t::RESTART_RECOVERED ? "RESTART " : "degraded: ") +
                 printable(a.participant) + " restarted at step " + std::to_string(a.restart_step) +
                 ", " + printable(a.restart_note);
        break;
      }
      case RunLog::Kind::kUtterance: {
        const auto& u = run.utterances[ref.index];
        e.kind = Kind::kSay;
        e.utime = u.utime;
        e.human_id = u.human_id;
        e.t_cross_s = u.t_cross_s;
        e.what = speechActName(u.speech_act);
        e.text = u.text;
        e.round = u.round;
        e.direction = directionName(u.direction);
        e.delivery = deliveryName(u.delivery);
        e.speech_start_s = u.speech_start_s;
        e.speech_duration_s = u.speech_duration_s;
        // A said line stays as it was before deliveries existed (golden transcripts compare it);
        // an utterance decided but not said says why in place of SAY.
        std::string verb = "SAY";
        if (u.delivery == utterance_t::DELIVERY_MUTED) {
          verb = "NOT SAID (muted)";
        } else if (u.delivery == utterance_t::DELIVERY_TOO_LATE) {
          verb = "NOT SAID (too late: its " + fixed(u.speech_duration_s, 2) +
                 " s of speech would end " +
                 fixed(u.speech_start_s + u.speech_duration_s - u.t_cross_s, 2) +
                 " s after the crossing)";
        } else if (u.delivery == utterance_t::DELIVERY_TOLD_TO_GROUP) {
          verb = "NOT SAID (told to the group)";
        } else if (u.delivery == utterance_t::DELIVERY_CONTRADICTS) {
          verb = "NOT SAID (would contradict)";
        }
        // Said to a group: who heard it with the human addressed.
        std::string with;
        for (std::size_t i = 0; i < u.group_ids.size(); ++i)
          with += (i ? "," : " with ") + std::to_string(u.group_ids[i]);
        e.line = prefix(e.utime, e.human_id, e.t_cross_s) + "  " + verb + " " + e.what + " " +
                 jsonQuote(e.text) + " (round " + std::to_string(e.round);
        if (u.direction != situation_t::DIR_UNDEFINED) e.line += ", direction " + e.direction;
        e.line += ")";
        if (u.delivery == utterance_t::DELIVERY_SAID && !with.empty()) e.line += with;
        break;
      }
      case RunLog::Kind::kRobotAction: {
        const auto& act = run.actions[ref.index];
        e.kind = Kind::kAction;
        e.utime = act.utime;
        e.human_id = act.human_id;
        e.t_cross_s = analysis.tCrossAt(run, act.human_id, act.utime);
        e.what = robotActionName(act.action);
        e.text = act.reason;
        e.line = prefix(e.utime, e.human_id, e.t_cross_s) + "  ACTION " + e.what + why(e.text);
        break;
      }
      case RunLog::Kind::kRecorderControl: {
        const auto& c = run.controls[ref.index];
        e.kind = Kind::kRecorder;
        e.utime = c.utime;
        e.human_id = c.human_id;
        e.t_cross_s = analysis.tCrossAt(run, c.human_id, c.utime);
        e.what = recorderCommandName(c.command);
        e.text = c.reason;
        e.line = prefix(e.utime, e.human_id, e.t_cross_s) + "  RECORDER " + e.what + why(e.text);
        break;
      }
      case RunLog::Kind::kSituation: {
        if (!options.include_unknown) continue;
        const auto& s = run.situations[ref.index];
        if (s.reason.empty()) continue;
        const auto key = std::make_pair(s.human_id, reasonKind(s.reason));
        if (unknown_first.count(key)) continue;
        if (reasons_per_human[s.human_id] >= options.max_unknown_reasons) continue;
        ++reasons_per_human[s.human_id];
        unknown_first[key] = ref.index;
        e.kind = Kind::kUnknown;
        e.utime = s.utime;
        e.human_id = s.human_id;
        e.t_cross_s = s.t_cross_s;
        e.what = crossingName(s.crossing_status);
        e.text = s.reason;
        e.line = prefix(e.utime, e.human_id, e.t_cross_s) + "  UNKNOWN crossing " + e.what +
                 ", needs " + predicateName(s.human_needs_to_contribute) + ", human_constrained " +
                 predicateName(s.human_is_constrained) + ", robot_constrained " +
                 predicateName(s.robot_is_constrained) + ": " + jsonQuote(s.reason) +
                 " (first of " + std::to_string(unknown_count[key]) + ")";
        break;
      }
      default:
        continue;
    }
    events.push_back(std::move(e));
  }
  // Messages of different daemons reach the logger in an order that may vary between runs;
  // the simulated time and the pipeline order within it do not.
  std::stable_sort(events.begin(), events.end(),
                   [](const TranscriptEntry& a, const TranscriptEntry& b) {
                     if (a.utime != b.utime) return a.utime < b.utime;
                     return rank(a.kind) < rank(b.kind);
                   });

  if (options.include_final_cm) {
    for (const auto& h : analysis.humans) {
      if (!h.last_assessment) continue;
      const auto& p = run.assessments[*h.last_assessment];
      TranscriptEntry e;
      e.kind = Kind::kFinalCm;
      e.utime = p.utime;
      e.human_id = p.human_id;
      e.t_cross_s = std::nan("");
      e.what = "CM";
      e.line = "t=" + fixed(utimeToS(p.utime), 2) + "s  human " + std::to_string(p.human_id) +
               "  FINAL CM window=" + fixed(p.cm_m, 3) + " m (" + std::to_string(p.window_samples) +
               " samples, IsContributing " + predicateName(p.is_contributing) +
               "), interaction=" + fixed(p.cm_interaction_m, 3) + " m (" +
               std::to_string(p.interaction_samples) + " samples, IsContributing " +
               predicateName(p.is_contributing_interaction) + "), gamma " + fixed(p.gamma, 2) +
               ", tau " + fixed(p.tau_m, 2) + " m";
      events.push_back(std::move(e));
    }
  }
  if (options.include_sim_status && analysis.final_status) {
    const auto& st = run.sim_status[*analysis.final_status];
    TranscriptEntry e;
    e.kind = Kind::kSimStatus;
    e.utime = st.utime;
    e.t_cross_s = std::nan("");
    e.what = simStateName(st.state);
    e.text = st.detail;
    e.line = "t=" + fixed(utimeToS(st.utime), 2) + "s  SIM " + e.what + "  step " +
             std::to_string(st.step) + "  min_clearance=" + fixed(st.min_clearance_m, 3) +
             "m  robot_time_to_goal=" + fixed(st.robot_time_to_goal_s, 2) +
             (std::isfinite(st.robot_time_to_goal_s) ? "s" : "");
    if (!st.detail.empty()) e.line += "  " + jsonQuote(st.detail);
    events.push_back(std::move(e));
  }
  return events;
}

std::string formatTranscript(const std::string& scenario,
                             const std::vector<TranscriptEntry>& entries) {
  std::string out =
      "# scenario " + (scenario.empty() ? std::string("(unnamed)") : printable(scenario)) + "\n";
  for (const auto& e : entries) out += e.line + "\n";
  return out;
}

}  // namespace coopnav::ctl
