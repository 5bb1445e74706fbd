#include "coopnav/dialogue/overtake_words.hpp"

#include <array>
#include <cstdio>

namespace coopnav::dialogue {

std::string renderPassing(const std::string& text, const TextTemplates& templates, Side side) {
  const std::string& word = side == Side::kLeft    ? templates.left_word
                            : side == Side::kRight ? templates.right_word
                                                   : std::string();
  std::string out = text;
  const std::string key = "{dir}";
  for (std::size_t at = out.find(key); at != std::string::npos; at = out.find(key, at)) {
    out.replace(at, key.size(), word);
    at += word.size();
  }
  return out;
}

DecisionOutput OvertakeWords::step(const Input& in, const OvertakeWordsConfig& config,
                                   const TextTemplates& templates) {
  DecisionOutput out;
  switch (state_) {
    case State::kFollowing: {
      if (!in.person || in.person->robot_side == Side::kUndefined || in.robot_making_room ||
          in.t_s < not_before_s_)
        break;
      const double clearance_m = lateralClearance(*in.person, in.robot_radius_m);
      if (clearance_m < config.pass_clearance_m || in.person->gap_m > config.announce_gap_m) break;
      state_ = State::kSaid;
      said_at_s_ = in.t_s;
      const Side side = in.person->robot_side;
      out.utterances.push_back(
          {SpeechAct::kInformDirection, side, 1, renderPassing(config.text, templates, side)});
      std::array<char, 128> why{};
      std::snprintf(why.data(), why.size(),
                    "overtake: ahead walking the robot's way, gap %.2f m, lane clears by %.2f m "
                    "-> say pass",
                    in.person->gap_m, clearance_m);
      out.rounds.push_back({1, in.t_s, in.t_cross_s, why.data(), ""});
      break;
    }
    case State::kSaid: {
      // Words first: the pass starts once they have been said (muted: at once, as if said).
      const bool said = in.heard_by_s && *in.heard_by_s > said_at_s_;
      if (!said && !in.muted) {
        state_ = State::kFollowing;
        not_before_s_ = in.t_s + config.retry_s;
        out.rounds.push_back(
            {1, in.t_s, in.t_cross_s, "overtake: words not said -> follow on", ""});
        break;
      }
      if ((said && in.t_s < *in.heard_by_s) || in.robot_making_room) break;
      state_ = State::kPassing;
      out.robot_actions.push_back(RobotAction::kGoFirst);
      out.rounds.push_back(
          {1, in.t_s, in.t_cross_s, "overtake: words said -> pass (go first)", ""});
      break;
    }
    case State::kPassing:
      break;
  }
  return out;
}

}  // namespace coopnav::dialogue
