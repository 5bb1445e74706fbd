#include "coopnav/dialogue/decision.hpp"

#include <array>
#include <cmath>
#include <cstdio>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav::dialogue {

namespace {

// Kleene comparison for StillNeedsToContribute = CM < d_h.
Tristate lessThan(std::optional<double> a, std::optional<double> b) {
  if (!a || !b || std::isnan(*a) || std::isnan(*b)) return Tristate::kUnknown;
  return toTristate(*a < *b);
}

}  // namespace

const char* toString(CooperationJudgement j) {
  switch (j) {
    case CooperationJudgement::kCm:
      return "cm";
    case CooperationJudgement::kForecast:
      return "forecast";
  }
  return "?";
}

bool parseCooperationJudgement(const std::string& s, CooperationJudgement& out) {
  for (const CooperationJudgement j : {CooperationJudgement::kCm, CooperationJudgement::kForecast})
    if (s == toString(j)) {
      out = j;
      return true;
    }
  return false;
}

Tristate judgeContributing(const DecisionConfig& config, const PathSnapshot& path) {
  if (config.judgement == CooperationJudgement::kCm) return path.is_contributing;
  if (!path.p_contributing || std::isnan(*path.p_contributing)) return Tristate::kUnknown;
  return toTristate(*path.p_contributing >= config.forecast_threshold);
}

std::string describeContributing(const DecisionConfig& config, const PathSnapshot& path) {
  const Tristate v = judgeContributing(config, path);
  const char* head = v == Tristate::kTrue    ? "contributing"
                     : v == Tristate::kFalse ? "!contributing"
                                             : "contributing unknown";
  if (config.judgement == CooperationJudgement::kCm) return head;
  std::array<char, 64> why{};
  if (v == Tristate::kUnknown)
    std::snprintf(why.data(), why.size(), " (p_contributing unknown)");
  else
    std::snprintf(why.data(), why.size(), " (p %.2f %s %.2f)", *path.p_contributing,
                  v == Tristate::kTrue ? ">=" : "<", config.forecast_threshold);
  return std::string("forecast ") + head + why.data();
}

const char* toString(SpeechAct a) {
  switch (a) {
    case SpeechAct::kInformDirection:
      return "inform_direction";
    case SpeechAct::kAskToMove:
      return "ask_to_move";
    case SpeechAct::kInformDockIfNeeded:
      return "inform_dock_if_needed";
    case SpeechAct::kRepeatDirection:
      return "repeat_direction";
    case SpeechAct::kAskToMoveMore:
      return "ask_to_move_more";
    case SpeechAct::kInformDocking:
      return "inform_docking";
    case SpeechAct::kInformWiderPlace:
      return "inform_wider_place";
    case SpeechAct::kInformRetreat:
      return "inform_retreat";
    case SpeechAct::kInformStopping:
      return "inform_stopping";
    case SpeechAct::kThank:
      return "thank";
    case SpeechAct::kInformGoingFirst:
      return "inform_going_first";
    case SpeechAct::kInformResuming:
      return "inform_resuming";
  }
  return "?";
}

const char* toString(RecorderCommand c) {
  switch (c) {
    case RecorderCommand::kStart:
      return "start";
    case RecorderCommand::kStop:
      return "stop";
    case RecorderCommand::kReset:
      return "reset";
  }
  return "?";
}

const char* toString(RoomPlan p) {
  switch (p) {
    case RoomPlan::kUnknown:
      return "unknown";
    case RoomPlan::kDockHere:
      return "dock_here";
    case RoomPlan::kWiderPlace:
      return "wider_place";
    case RoomPlan::kRetreat:
      return "retreat";
    case RoomPlan::kNone:
      return "none";
  }
  return "?";
}

const char* toString(RobotAction a) {
  switch (a) {
    case RobotAction::kDock:
      return "dock";
    case RobotAction::kResume:
      return "resume";
    case RobotAction::kGoFirst:
      return "go_first";
    case RobotAction::kSlow:
      return "slow";
  }
  return "?";
}

std::string renderText(const TextTemplates& templates, SpeechAct act, Side dir) {
  std::string text;
  switch (act) {
    case SpeechAct::kInformDirection:
      text = templates.inform_direction;
      break;
    case SpeechAct::kAskToMove:
      text = templates.ask_to_move;
      break;
    case SpeechAct::kInformDockIfNeeded:
      text = templates.inform_dock_if_needed;
      break;
    case SpeechAct::kRepeatDirection:
      text = templates.repeat_direction;
      break;
    case SpeechAct::kAskToMoveMore:
      text = templates.ask_to_move_more;
      break;
    case SpeechAct::kInformDocking:
      text = templates.inform_docking;
      break;
    case SpeechAct::kInformWiderPlace:
      text = templates.inform_wider_place;
      break;
    case SpeechAct::kInformRetreat:
      text = templates.inform_retreat;
      break;
    case SpeechAct::kInformStopping:
      text = templates.inform_stopping;
      break;
    case SpeechAct::kThank:
      text = templates.thank;
      break;
    case SpeechAct::kInformGoingFirst:
      text = templates.inform_going_first;
      break;
    case SpeechAct::kInformResuming:
      text = templates.inform_resuming;
      break;
  }
  const std::string word = dir == Side::kLeft
                               ? templates.left_word
                               : (dir == Side::kRight ? templates.right_word : std::string());
  static const std::string kPlaceholder = "{dir}";
  for (std::size_t pos = text.find(kPlaceholder); pos != std::string::npos;
       pos = text.find(kPlaceholder, pos + word.size())) {
    text.replace(pos, kPlaceholder.size(), word);
  }
  return text;
}

std::vector<std::string> wordings(const TextTemplates& templates, const Utterance& u) {
  std::vector<std::string> out{u.text};
  // The short form belongs to the long text it shortens, said alone or after the crowd's
  // address ("You two ahead, I will wait here ..."; crowd.hpp), which it keeps.
  std::string address;
  auto is = [&](const std::string& full) {
    if (u.text == full) return true;
    const std::string tail = ", " + full;
    if (u.text.size() > tail.size() &&
        u.text.compare(u.text.size() - tail.size(), tail.size(), tail) == 0) {
      address = u.text.substr(0, u.text.size() - full.size());
      return true;
    }
    return false;
  };
  const std::string* shorter = nullptr;
  if (u.act == SpeechAct::kInformDocking && is(templates.inform_docking))
    shorter = &templates.inform_docking_short;
  else if (u.act == SpeechAct::kInformDocking && is(templates.inform_precautionary_docking))
    shorter = &templates.inform_precautionary_docking_short;
  else if (u.act == SpeechAct::kInformWiderPlace && is(templates.inform_wider_place))
    shorter = &templates.inform_wider_place_short;
  else if (u.act == SpeechAct::kInformRetreat && is(templates.inform_retreat))
    shorter = &templates.inform_retreat_short;
  else if (u.act == SpeechAct::kInformStopping && is(templates.inform_stopping))
    shorter = &templates.inform_stopping_short;
  if (shorter != nullptr && !shorter->empty() && address + *shorter != u.text)
    out.push_back(address + *shorter);
  return out;
}

HumanDecision::HumanDecision(const DecisionConfig& config)
    : config_(config), watch_(config.stand_off) {}

bool HumanDecision::roundFired(int round) const {
  return round >= 1 && round <= 3 && fired_[round - 1];
}

void HumanDecision::say(SpeechAct act, Side dir, int round, DecisionOutput& out) const {
  out.utterances.push_back({act, dir, round, renderText(config_.templates, act, dir)});
}

DecisionOutput HumanDecision::step(const DecisionInput& in) {
  DecisionOutput out;
  if (ended_) return out;
  const auto& t_cross = in.situation.t_cross_s;
  const bool t_cross_known = t_cross && std::isfinite(*t_cross);
  bool fired_round1_now = false;
  if (!in.crossed && t_cross_known) {
    // Only a human being crossed starts an interaction (DecisionConfig::crossing_range_m).
    const bool crossing = *t_cross > 0.0 && (!in.situation.d_hr_m ||
                                             *in.situation.d_hr_m <= config_.crossing_range_m);
    if (!fired_[0] && *t_cross <= config_.round1_t_cross_s && crossing) {
      round1(in, out);
      fired_round1_now = true;
    }
    // Round 2 never in the same step as round 1: its CM needs samples since the recorder start.
    // ... and not before the human could have acted on round 1's words (round2_response_s),
    // unless the crossing is too near to wait longer.
    const bool responded = config_.round2_response_s <= 0.0 || !in.heard_by_s ||
                           in.t_s >= *in.heard_by_s + config_.round2_response_s ||
                           *t_cross <= config_.round2_latest_t_cross_s;
    // A round 2 waiting for evidence (make_time) is decided at a later step whatever t_CROSS
    // does meanwhile: the slowed robot makes it grow.
    const bool due = round2_deferred_ || (*t_cross <= config_.round2_t_cross_s && responded);
    if (fired_[0] && !fired_round1_now && !fired_[1] && due && !deferRound2(in, out)) {
      round2(in, out);
      // Decided: the robot goes on at full speed unless it now makes room (DOCK replaces SLOW).
      if (slowed_ && !docked_) out.robot_actions.push_back(RobotAction::kResume);
    }
  }
  if (in.crossed && !fired_[2]) round3(in, out);
  announceRetreat(in, out);
  // A stand-off is watched until the crossing; from round 1 (the robot has spoken) all of them.
  // Before it only the robot backing off before a person who follows: with no crossing ahead
  // (the bands yield ground) round 1 would never come, while a wait before it may be someone
  // pausing or standing aside with nothing to resolve. Round 1 starts the watch afresh.
  if (config_.resolve_stand_offs && !in.crossed && !ended_ && in.motion) {
    if (fired_round1_now) watch_.restart();
    StandOff what = watch_.update(*in.motion, docked_);
    if (!fired_[0] && what != StandOff::kBackingOff) what = StandOff::kNone;
    if (what != StandOff::kNone) resolveStandOff(in, what, out);
  }
  // The band source acts on the latest action: any after a SLOW ends the slowing.
  if (!out.robot_actions.empty()) slowed_ = out.robot_actions.back() == RobotAction::kSlow;
  return out;
}

// Not in the paper (MakeTimeConfig): round 2 is due; wait, slowed, while the forecast cannot yet
// tell on the branch that reads it.
bool HumanDecision::deferRound2(const DecisionInput& in, DecisionOutput& out) {
  const MakeTimeConfig& mt = config_.make_time;
  if (!mt.enabled || config_.judgement != CooperationJudgement::kForecast) return false;
  const SituationSnapshot& s = in.situation;
  const double t_cross = *s.t_cross_s;  // known: step() checked it
  // Only the branch that reads the judgement waits: the others decide nothing on the person.
  if (lessThan(in.path.cm_window_m, s.d_h_m) != Tristate::kTrue ||
      s.robot_is_constrained != Tristate::kTrue)
    return false;
  const std::optional<double>& p = in.path.p_contributing;
  const bool decisive =
      p && std::isfinite(*p) && (*p >= mt.confidence || *p <= 1.0 - mt.confidence);
  if (decisive || t_cross <= mt.latest_t_cross_s) return false;
  if (!round2_deferred_) {
    round2_deferred_ = true;
    RoundOutcome r{2, in.t_s, s.t_cross_s, "", ""};
    r.deferred = true;
    std::array<char, 96> why{};
    if (p && std::isfinite(*p))
      std::snprintf(why.data(), why.size(), "p_contributing %.2f within (%.2f, %.2f)", *p,
                    1.0 - mt.confidence, mt.confidence);
    else
      std::snprintf(why.data(), why.size(), "p_contributing unknown");
    r.branch = "still & robot_constrained & forecast undecided -> slow, wait";
    std::array<char, 64> until{};
    std::snprintf(until.data(), until.size(), "; decided by t_cross %.1f s", mt.latest_t_cross_s);
    r.reason = std::string(why.data()) + until.data();
    out.rounds.push_back(r);
    out.robot_actions.push_back(RobotAction::kSlow);
  }
  return true;
}

// Not in the paper (stand_off.hpp). Who goes is decided by the cooperation assessment, the
// paper's own judgement of the person: one who made room is passed, not waited for.
void HumanDecision::resolveStandOff(const DecisionInput& in, StandOff what, DecisionOutput& out) {
  const SituationSnapshot& s = in.situation;
  const Tristate still = lessThan(in.path.cm_window_m, s.d_h_m);
  // Made room, and the passage fits: the robot's plan needs nothing more of the person now, or
  // they moved the d_h it needed (CM >= d_h), or they are moving aside while the robot has room
  // of its own.
  const bool made_room = s.human_needs_to_contribute == Tristate::kFalse ||
                         still == Tristate::kFalse ||
                         (judgeContributing(config_, in.path) == Tristate::kTrue &&
                          s.robot_is_constrained == Tristate::kFalse);
  const double waited_s = what == StandOff::kMutualWait   ? watch_.mutualWait_s()
                          : what == StandOff::kBackingOff ? watch_.backingOff_s()
                                                          : watch_.dockWait_s();
  RoundOutcome r{2, in.t_s, s.t_cross_s, "", ""};
  std::array<char, 32> waited{};
  std::snprintf(waited.data(), waited.size(), "%.1f", waited_s);
  std::string head = std::string("stand-off: ") + toString(what) + " " + waited.data() + " s";
  watch_.restart();
  if (!fired_[0]) {
    // The robot speaks first here: this decision takes the place of rounds 1 and 2, whose
    // words would now contradict it (round 3 still closes the interaction at the crossing).
    fired_[0] = fired_[1] = true;
    head = "before round 1: " + head;
  }
  if (docked_) {
    out.robot_actions.push_back(RobotAction::kResume);
    docked_ = false;
    if (made_room) {
      r.branch = head + " & docked & made room -> go first";
      say(SpeechAct::kInformGoingFirst, Side::kUndefined, 2, out);
    } else {
      r.branch = head + " & docked & !made room -> resume";
      say(SpeechAct::kInformResuming, Side::kUndefined, 2, out);
    }
    out.utterances.back().resolves_stand_off = true;
  } else if (made_room && !config_.go_first_when_not_docked) {
    r.branch = head + " & made room -> silent";
    r.reason = "the robot is not docked and does not go first (stand_off.go_first false)";
  } else if (made_room && !went_first_) {
    // The planner's bands still bend round the person who stands aside and stall the robot:
    // the band source drives past them on its side, guarded (robot_action_t.ACTION_GO_FIRST).
    r.branch = head + " & made room -> go first";
    went_first_ = true;
    out.robot_actions.push_back(RobotAction::kGoFirst);
    say(SpeechAct::kInformGoingFirst, Side::kUndefined, 2, out);
    out.utterances.back().resolves_stand_off = true;
  } else {
    // Not made room, or going first did not end the wait (the guard kept the robot back): the
    // robot makes room, and says so. Again after a dock that ended (the person did not come, or
    // the robot went on and met them again): a stand-off is never left to silence; every dock
    // ends, by the person passing or by its bounded wait, with words (issue 44).
    r.branch = head + (made_room ? " & made room & went first" : " & !made room") +
               (docked_ever_ ? " & docked before -> dock again" : " -> dock");
    const std::size_t first = out.utterances.size();
    dock(out, false, s.room_plan);
    dock_resolves_stand_off_ = true;
    for (std::size_t k = first; k < out.utterances.size(); ++k)
      out.utterances[k].resolves_stand_off = true;
  }
  out.rounds.push_back(r);
}

// Not in the paper: a dock that leaves too little room becomes a retreat in the band
// source when the human keeps closing; the human hears it once.
void HumanDecision::announceRetreat(const DecisionInput& in, DecisionOutput& out) {
  if (!docked_ || retreat_said_ || !in.situation.robot_retreating || in.crossed) return;
  retreat_said_ = true;
  say(SpeechAct::kInformRetreat, Side::kUndefined, 2, out);
  // A dock that resolved a stand-off escalated: nobody is going yet, no crossing to be late for.
  out.utterances.back().resolves_stand_off = dock_resolves_stand_off_;
}

// Paper §II-D, round 1 (design-readings, "Decision pipeline").
void HumanDecision::round1(const DecisionInput& in, DecisionOutput& out) {
  fired_[0] = true;
  const SituationSnapshot& s = in.situation;
  RoundOutcome r{1, in.t_s, s.t_cross_s, "", ""};
  // The recording starts whatever is said: round 2 and round 3 read it.
  out.recorder_commands.push_back(RecorderCommand::kStart);
  out.start_d_oh_m = s.d_oh_m;
  out.start_d_h_m = s.d_h_m;
  recorder_started_ = true;

  auto sayDir = [&](SpeechAct act, Side side, const char* branch) {
    r.branch = branch;
    if (side == Side::kUndefined) {
      r.reason = "Dir undefined: no side to speak";
      return;
    }
    say(act, side, 1, out);
  };

  if (s.human_needs_to_contribute == Tristate::kTrue) {
    if (s.robot_is_constrained == Tristate::kFalse) {
      sayDir(SpeechAct::kInformDirection, s.dir, "needs & !robot_constrained -> inform Dir");
    } else if (s.robot_is_constrained == Tristate::kTrue) {
      if (s.human_is_constrained == Tristate::kFalse) {
        sayDir(SpeechAct::kAskToMove, opposite(s.dir),
               "needs & robot_constrained & !human_constrained -> ask to move away");
      } else if (s.human_is_constrained == Tristate::kTrue) {
        r.branch = "needs & robot_constrained & human_constrained -> dock if needed";
        say(SpeechAct::kInformDockIfNeeded, Side::kUndefined, 1, out);
      } else {
        r.branch = "needs & robot_constrained & human_constrained unknown";
        r.reason = "HumanIsConstrained unknown: silent";
      }
    } else {
      r.branch = "needs & robot_constrained unknown";
      r.reason = "RobotIsConstrained unknown: silent";
    }
  } else if (s.human_needs_to_contribute == Tristate::kFalse) {
    // The paper's "if the human is not constrained" read as the else branch of
    // HumanNeedsToContribute (design-readings).
    if (s.robot_is_constrained == Tristate::kTrue) {
      sayDir(SpeechAct::kInformDirection, s.dir, "!needs & robot_constrained -> inform Dir");
    } else if (s.robot_is_constrained == Tristate::kFalse) {
      r.branch = "!needs & !robot_constrained -> silent";
    } else {
      r.branch = "!needs & robot_constrained unknown";
      r.reason = "RobotIsConstrained unknown: silent";
    }
  } else {
    r.branch = "needs unknown";
    r.reason = "HumanNeedsToContribute unknown: silent";
  }
  out.rounds.push_back(r);
}

// Paper §II-D, round 2: StillNeedsToContribute = CM < d_h.
void HumanDecision::round2(const DecisionInput& in, DecisionOutput& out) {
  fired_[1] = true;
  const SituationSnapshot& s = in.situation;
  RoundOutcome r{2, in.t_s, s.t_cross_s, "", ""};
  const Tristate still = lessThan(in.path.cm_window_m, s.d_h_m);
  if (config_.precautionary_dock && precautionaryDock(in, still, r, out)) {
    out.rounds.push_back(r);
    return;
  }
  if (still == Tristate::kTrue) {
    if (s.robot_is_constrained == Tristate::kFalse) {
      r.branch = "still & !robot_constrained -> repeat Dir";
      if (s.dir == Side::kUndefined) {
        r.reason = "Dir undefined: no side to speak";
      } else {
        say(SpeechAct::kRepeatDirection, s.dir, 2, out);
      }
    } else if (s.robot_is_constrained == Tristate::kTrue) {
      // Read IsContributing (or the forecast: DecisionConfig::judgement), then reset the
      // recorder (the snapshot was read before the reset).
      const Tristate contributing = judgeContributing(config_, in.path);
      const std::string judged =
          "still & robot_constrained & " + describeContributing(config_, in.path);
      out.recorder_commands.push_back(RecorderCommand::kReset);
      if (contributing == Tristate::kTrue) {
        r.branch = judged + " -> ask to move more";
        if (s.dir == Side::kUndefined) {
          r.reason = "Dir undefined: no side to speak";
        } else {
          say(SpeechAct::kAskToMoveMore, opposite(s.dir), 2, out);
        }
      } else if (contributing == Tristate::kFalse) {
        r.branch = judged + " -> dock";
        dock(out, false, s.room_plan);
      } else {
        r.branch = judged;
        r.reason = config_.judgement == CooperationJudgement::kCm
                       ? "IsContributing unknown: no dock, silent"
                       : "p_contributing unknown: no dock, silent";
      }
    } else {
      r.branch = "still & robot_constrained unknown";
      r.reason = "RobotIsConstrained unknown: silent";
    }
  } else if (still == Tristate::kFalse) {
    r.branch = "!still -> silent";
  } else {
    r.branch = "still unknown";
    r.reason = std::string("StillNeedsToContribute unknown (CM ") +
               (in.path.cm_window_m ? "known" : "unknown") + ", d_h " +
               (s.d_h_m ? "known" : "unknown") + "): silent";
  }
  out.rounds.push_back(r);
}

namespace {

std::string describe(Tristate v, const char* name) {
  if (v == Tristate::kTrue) return name;
  if (v == Tristate::kFalse) return std::string("!") + name;
  return std::string(name) + " unknown";
}

}  // namespace

// Not in the paper (see DecisionConfig::precautionary_dock). The flowchart's own branches are
// left to round2() whenever its inputs decide them: a dock there needs still, robot constrained
// and not contributing all known; here one of them (or CM / d_h behind still) is unknown.
bool HumanDecision::precautionaryDock(const DecisionInput& in, Tristate still, RoundOutcome& r,
                                      DecisionOutput& out) {
  const SituationSnapshot& s = in.situation;
  const Tristate robot = s.robot_is_constrained;
  const Tristate contributing = judgeContributing(config_, in.path);
  const bool any_unknown =
      still == Tristate::kUnknown || robot == Tristate::kUnknown ||
      (robot == Tristate::kTrue && still == Tristate::kTrue && contributing == Tristate::kUnknown);
  // Known facts that make a dock unnecessary: the human moved enough, the robot has room, the
  // human is moving aside (the flowchart then asks for more, it never docks).
  if (!any_unknown || still == Tristate::kFalse || robot == Tristate::kFalse ||
      contributing == Tristate::kTrue)
    return false;
  r.branch = describe(still, "still") + " & " + describe(robot, "robot_constrained") + " & " +
             describeContributing(config_, in.path) + " -> degraded: precautionary dock";
  std::string unknown;
  auto add = [&unknown](const std::string& what) {
    unknown += (unknown.empty() ? "" : ", ") + what;
  };
  if (robot == Tristate::kUnknown) add("RobotIsConstrained");
  if (!in.path.cm_window_m) add("CM");
  if (!s.d_h_m) add("d_h");
  if (contributing == Tristate::kUnknown)
    add(config_.judgement == CooperationJudgement::kCm ? "IsContributing" : "p_contributing");
  r.reason = unknown + " unknown near the crossing" + (s.reason.empty() ? "" : ": " + s.reason);
  r.degraded = true;
  // As a flowchart dock: the recorder restarts, so that round 3 judges the human from here.
  out.recorder_commands.push_back(RecorderCommand::kReset);
  dock(out, true, s.room_plan);
  return true;
}

// Round 2's dock, from the flowchart or as a precaution: request it and tell the human.
void HumanDecision::dock(DecisionOutput& out, bool precautionary, RoomPlan room) {
  out.robot_actions.push_back(RobotAction::kDock);
  docked_ = true;
  docked_ever_ = true;
  dock_resolves_stand_off_ = false;  // resolveStandOff sets it after the call
  // What the robot will really do (the band source checked the passage its dock would leave):
  // the promise must hold. Unknown keeps the paper's sentence.
  const SpeechAct concrete = room == RoomPlan::kWiderPlace ? SpeechAct::kInformWiderPlace
                             : room == RoomPlan::kRetreat  ? SpeechAct::kInformRetreat
                             : room == RoomPlan::kNone     ? SpeechAct::kInformStopping
                                                           : SpeechAct::kInformDocking;
  // Each dock is its own promise: a retreat it escalates to is announced anew (announceRetreat).
  retreat_said_ = concrete == SpeechAct::kInformRetreat;
  if (concrete != SpeechAct::kInformDocking) {
    say(concrete, Side::kUndefined, 2, out);
  } else if (precautionary) {
    out.utterances.push_back({SpeechAct::kInformDocking, Side::kUndefined, 2,
                              config_.templates.inform_precautionary_docking});
  } else {
    say(SpeechAct::kInformDocking, Side::kUndefined, 2, out);
  }
}

// Paper §II-D, round 3: after crossing, stop the recorder; thank if the human facilitated.
void HumanDecision::round3(const DecisionInput& in, DecisionOutput& out) {
  fired_[2] = true;
  ended_ = true;
  RoundOutcome r{3, in.t_s, std::nullopt, "", ""};
  if (recorder_started_) out.recorder_commands.push_back(RecorderCommand::kStop);
  if (docked_ || slowed_) {
    out.robot_actions.push_back(RobotAction::kResume);
    docked_ = false;
  }
  if (!fired_[0]) {
    r.branch = "crossed before round 1";
    r.reason = "no assessment was recorded: silent";
  } else if (in.path.is_contributing == Tristate::kTrue) {
    r.branch = "crossed & contributing -> thank";
    say(SpeechAct::kThank, Side::kUndefined, 3, out);
  } else {
    r.branch = "crossed & !contributing -> silent";
    if (in.path.is_contributing == Tristate::kUnknown) r.reason = "IsContributing unknown: silent";
  }
  out.rounds.push_back(r);
}

DecisionOutput HumanDecision::endInteraction(double t_s, const std::string& reason) {
  DecisionOutput out;
  if (ended_) return out;
  ended_ = true;
  if (recorder_started_ && !fired_[2]) out.recorder_commands.push_back(RecorderCommand::kStop);
  if (docked_ || slowed_) {
    out.robot_actions.push_back(RobotAction::kResume);
    docked_ = false;
    slowed_ = false;
  }
  out.rounds.push_back({0, t_s, std::nullopt, "interaction ended", reason});
  return out;
}

double robotAlongHumanHeading_m(const Pose2& human, const Eigen::Vector2d& robot_m) {
  return headingVector(human.theta_rad).dot(robot_m - human.position());
}

CrossedTracker updateCrossed(CrossedTracker previous, const Pose2& human,
                             const Eigen::Vector2d& robot_m, double hysteresis_m,
                             double max_distance_m) {
  if (previous.crossed || !isFinite(human) || !robot_m.allFinite()) return previous;
  if (!previous.seen_ahead) {
    // Hysteresis: a robot hovering around the human's lateral line (along ≈ 0) flips no state.
    if (robotAlongHumanHeading_m(human, robot_m) > hysteresis_m) {
      previous.seen_ahead = true;
      previous.axis = headingVector(human.theta_rad);
    }
    return previous;
  }
  const double along_m = previous.axis.dot(robot_m - human.position());
  if (along_m < -hysteresis_m && (robot_m - human.position()).norm() <= max_distance_m)
    previous.crossed = true;
  return previous;
}

}  // namespace coopnav::dialogue
