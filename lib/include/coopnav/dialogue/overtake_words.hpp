#pragma once
/// @file What the robot says behind a person ahead walking its way (geometry/same_way.hpp), and
/// when it may pass them. Not in the paper, whose flowchart is for a person coming towards the
/// robot: read for a person walking away ahead, it asks them to make room or says the robot
/// waits for them to pass (issue 44). Here the robot follows in silence (the band source holds
/// it a comfortable gap behind, in the lane beside them where one fits); once it is in that lane
/// (its body clears theirs by pass_clearance_m if it drives straight on) and near, it says "Excuse
/// me, I will pass on your left." (the side it is on), and when the words have been said it asks
/// the band source to pass (robot action GO_FIRST for that person). Words first, then the
/// action, on the side the words name. Pure: time is an input.

#include <optional>
#include <string>

#include "coopnav/dialogue/decision.hpp"
#include "coopnav/geometry/same_way.hpp"

namespace coopnav::dialogue {

/// config/dialogue_manager.yaml `overtake`. Defaults in this one place.
struct OvertakeWordsConfig {
  /// false: a person ahead walking the robot's way is decided on by the paper's flowchart.
  bool enabled{true};
  SameWayOptions same_way;
  /// [m] The robot's body clears the person's by at least this if it drives straight on: it is
  /// in the lane beside them. The safety guard's min_clearance_m (0.2): a lane nearer than that
  /// would have the guard stop the pass the words announce.
  double pass_clearance_m{0.2};
  /// [m] Said within this surface gap of the person: near enough to be about to pass.
  double announce_gap_m{3.0};
  /// [s] Words decided but not said are decided again no sooner than this.
  double retry_s{3.0};
  /// "{dir}" is the robot's side as the person sees it (TextTemplates' left / right words).
  std::string text{"Excuse me, I will pass on your {dir}."};
};

/// Per person ahead walking the robot's way.
class OvertakeWords {
 public:
  enum class State { kFollowing, kSaid, kPassing };

  struct Input {
    double t_s{0.0};
    std::optional<double> t_cross_s;
    /// The person as the robot sees them now; nullopt when they are not ahead walking its way.
    std::optional<SameWayPerson> person;
    double robot_radius_m{0.47};
    /// [s] When the words said to the person so far end; nullopt: nothing said (or muted).
    std::optional<double> heard_by_s;
    /// The robot says nothing (SessionConfig::muted): it acts as if it had.
    bool muted{false};
    /// The robot makes room for someone (docked, retreating): no pass is announced or begun.
    bool robot_making_room{false};
  };

  /// The words, then GO_FIRST once they have been said; words decided but not said (not
  /// muted: told to a group, or contradicting what another was told) are no pass: the robot
  /// follows on and may say them again later.
  DecisionOutput step(const Input& in, const OvertakeWordsConfig& config,
                      const TextTemplates& templates);
  State state() const { return state_; }
  /// The pass was announced: the person is the robot's to pass, not the flowchart's.
  bool engaged() const { return state_ != State::kFollowing; }

 private:
  State state_{State::kFollowing};
  double said_at_s_{0.0};
  double not_before_s_{-1e300};  ///< [s] no words before this (a retry)
};

/// `text` with every "{dir}" replaced by the templates' word for `side`.
std::string renderPassing(const std::string& text, const TextTemplates& templates, Side side);

}  // namespace coopnav::dialogue
