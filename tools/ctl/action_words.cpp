#include "action_words.hpp"

#include <algorithm>

#include "run_analysis.hpp"
#include "transcript.hpp"

namespace coopnav::ctl {
namespace {

/// Words that tell their human the robot goes on (passes on a side, asks them to make room, or
/// ends a stand-off by going).
bool tellsRobotPasses(std::int8_t act) {
  return act == utterance_t::ACT_INFORM_DIRECTION || act == utterance_t::ACT_REPEAT_DIRECTION ||
         act == utterance_t::ACT_ASK_TO_MOVE || act == utterance_t::ACT_ASK_TO_MOVE_MORE ||
         act == utterance_t::ACT_INFORM_GOING_FIRST || act == utterance_t::ACT_INFORM_RESUMING;
}

/// Words that tell their human the robot makes room (or may: "I will wait at the side if
/// needed.").
bool tellsRobotMakesRoom(std::int8_t act) {
  return act == utterance_t::ACT_INFORM_DOCK_IF_NEEDED || act == utterance_t::ACT_INFORM_DOCKING ||
         act == utterance_t::ACT_INFORM_WIDER_PLACE || act == utterance_t::ACT_INFORM_RETREAT ||
         act == utterance_t::ACT_INFORM_STOPPING;
}

/// Words that reach human `id`: addressed to them, or said to their group.
bool reaches(const utterance_t& u, std::int32_t id) {
  return u.human_id == id ||
         std::find(u.group_ids.begin(), u.group_ids.end(), id) != u.group_ids.end();
}

std::string at(std::int64_t utime) { return fixed(utimeToS(utime), 2) + " s"; }

}  // namespace

ActionWordsCheck checkActionWords(const RunLog& run) {
  ActionWordsCheck out;
  const auto window_us = static_cast<std::int64_t>(kActionWordsWindow_s * 1e6);
  for (const auto& a : run.actions) {
    // A dock makes room; going first passes the person (a RESUME ends a dock the person heard
    // announced, with its own words, and is not checked here).
    const bool makes_room = a.action == robot_action_t::ACTION_DOCK;
    if (!makes_room && a.action != robot_action_t::ACTION_GO_FIRST) continue;
    const auto sayingSo = [&](std::int8_t act) {
      return makes_room ? tellsRobotMakesRoom(act) : tellsRobotPasses(act);
    };
    // What the robot last said to this human about its own plan before the action.
    const utterance_t* told = nullptr;
    for (const auto& u : run.utterances) {
      if (u.utime > a.utime || !wasSaid(u.delivery) || !reaches(u, a.human_id)) continue;
      if (tellsRobotPasses(u.speech_act) || tellsRobotMakesRoom(u.speech_act)) told = &u;
    }
    // Going first needs words even if nothing was said before: the person waits for the robot.
    if (makes_room && (told == nullptr || sayingSo(told->speech_act))) continue;
    if (!makes_room && told != nullptr && sayingSo(told->speech_act) &&
        told->speech_act == utterance_t::ACT_INFORM_GOING_FIRST)
      continue;
    // Passing a person ahead walking the robot's way (decided "overtake: ...",
    // lib/dialogue/overtake_words.hpp) after telling them the side: "Excuse me, I will pass on
    // your left." are its words of going.
    if (!makes_room && told != nullptr && told->speech_act == utterance_t::ACT_INFORM_DIRECTION &&
        a.reason.find("overtake:") != std::string::npos)
      continue;
    // Words saying so decided with the action.
    const utterance_t* with = nullptr;
    for (const auto& u : run.utterances) {
      if (u.utime < a.utime || u.utime > a.utime + window_us || !reaches(u, a.human_id) ||
          !sayingSo(u.speech_act))
        continue;
      if (wasSaid(u.delivery)) {
        with = &u;
        break;
      }
      if (u.delivery == utterance_t::DELIVERY_TOO_LATE && with == nullptr) with = &u;
    }
    const std::string what =
        at(a.utime) + " human " + std::to_string(a.human_id) + " " + robotActionName(a.action) +
        (told == nullptr ? std::string(": told nothing")
                         : ": told " + speechActName(told->speech_act) + " round " +
                               std::to_string(told->round) + " at " + at(told->utime) + " (\"" +
                               told->text + "\")");
    if (with == nullptr) {
      out.contradictions.push_back(
          what + (makes_room ? ", no words of making room" : ", no words of going"));
    } else if (!wasSaid(with->delivery)) {
      out.unsaid_too_late.push_back(what + ", " + speechActName(with->speech_act) +
                                    " not said: too late (\"" + with->text + "\")");
    }
  }
  return out;
}

}  // namespace coopnav::ctl
