#pragma once
/// @file Words against actions, read from the log alone (summary.json
/// dialogue_checks.action_contradicts_words): an action that changes what the robot told someone
/// must come with words that say so. A dock for human h after h (or h's group) was told the robot
/// passes ("I am passing on your right.", or asked to move aside) and before any said words of
/// making room ("I will wait here ...", "I will back up ...", "... at the side if needed.") is a
/// contradiction unless words of making room for h are decided with it (within
/// kActionWordsWindow_s): said, or logged as not said because too late (the transcript then says
/// what was not said and why; listed apart, not a failure). Going first (GO_FIRST, a stand-off's
/// end: the person waits for the robot) comes with words of going ("Thank you, I will go
/// first.") decided with it, unless those were the last words said to h.

#include <string>
#include <vector>

#include "logfile/log_reader.hpp"

namespace coopnav::ctl {

/// How long after an action its words may be decided and still come with it [s]: two decision
/// cycles at the nodes' 10 Hz (the words of a dock are decided at the dock's step or the next).
inline constexpr double kActionWordsWindow_s = 0.25;

struct ActionWordsCheck {
  /// "<t> s human <id> DOCK: told INFORM_DIRECTION round 1 at <t0> s ("text"), no words of making
  /// room"
  std::vector<std::string> contradictions;
  /// Docks whose words of making room were decided but too late to say (DELIVERY_TOO_LATE).
  std::vector<std::string> unsaid_too_late;
};

ActionWordsCheck checkActionWords(const RunLog& run);

}  // namespace coopnav::ctl
