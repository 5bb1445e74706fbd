#pragma once
/// @file Speaking to several people at once. The paper's decision pipeline (§II-D, decision.hpp)
/// runs per human; with more than one person in the scene its words need three things the paper,
/// with one human, never had to say:
///  - who they are for: an address in front of the sentence ("You on my left, ..."), since the
///    robot has no names to call people by (the tracker's ids are not theirs);
///  - one plan per group: people walking together (or standing together) are told once, as a
///    group, and never asked to part to either side of the robot;
///  - no contradiction: while the robot makes room for someone (a dock, a wider place, a retreat,
///    a stop), it tells nobody else that it is passing them.
/// Pure: positions and times are inputs; the dialogue manager calls it once per step with the
/// utterances each human's decision produced.

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "coopnav/dialogue/decision.hpp"
#include "coopnav/geometry/types.hpp"

namespace coopnav::dialogue {

/// A human of the scene as the crowd logic sees it (world frame).
struct CrowdMember {
  std::int32_t id{0};
  Eigen::Vector2d position_m{Eigen::Vector2d::Zero()};
  Eigen::Vector2d velocity_m_s{Eigen::Vector2d::Zero()};
};

/// Tuning of groups and addresses. Defaults in this one place.
struct CrowdConfig {
  /// [m] two people at most this far apart (centres) may walk or stand together. Walking groups
  /// keep ~0.7-1.0 m between neighbours (Moussaïd et al. 2010, PLoS ONE 5(4)) and
  /// conversing groups stand within personal distance (Hall: < 1.2 m between bodies, ~1.5 m
  /// between centres); farther apart they are two people who happen to be near.
  double group_distance_m{1.5};
  /// [m/s] ... and move alike: their velocities differ by at most this much (people walking
  /// together match speed and heading; two strangers crossing side by side do not).
  double group_velocity_diff_m_s{0.3};
  /// [rad] addressees whose bearing from the robot's heading is within this are "ahead".
  double ahead_half_angle_rad{0.35};
};

/// Groups of the scene: people linked when they are within group_distance_m and their velocities
/// differ by at most group_velocity_diff_m_s, a group being everyone linked through a chain of
/// such links. Every member is in exactly one group (alone: a group of one). Members of a group
/// are sorted by id; groups by their smallest id.
std::vector<std::vector<std::int32_t>> findGroups(const std::vector<CrowdMember>& scene,
                                                  const CrowdConfig& config);

/// The words that say whom a sentence is for, from where the addressees are around the robot:
/// "You ahead", "You on my left", "You two on my right", "All of you ahead" (more than five).
/// Ahead / left / right from the bearing of the addressees' centroid in the robot's frame.
std::string addressPhrase(const Pose2& robot, const std::vector<Eigen::Vector2d>& addressees_m,
                          const CrowdConfig& config);

/// What the crowd logic made of one decided utterance.
enum class CrowdVerdict : std::int8_t {
  kSay = 1,          ///< said, addressed (also to `group`) when the scene holds several people
  kToldToGroup = 2,  ///< this round's plan was already said to the human's group: not repeated
  kContradicts = 3,  ///< saying it would contradict what the robot said or does: not said
};
const char* toString(CrowdVerdict v);

/// An utterance one human's decision produced at this step.
struct DecidedUtterance {
  std::int32_t human_id{0};
  Utterance utterance;
  std::size_t tag{0};  ///< the caller's, copied to the result (to find its own entry again)
};

struct CoordinatedUtterance {
  std::int32_t human_id{0};
  Utterance utterance;  ///< text with the address in front when kSay in a scene of several
  CrowdVerdict verdict{CrowdVerdict::kSay};
  std::vector<std::int32_t> group;  ///< the other members of the human's group (sorted)
  std::string reason;               ///< why not said ("" for kSay)
  std::size_t tag{0};               ///< DecidedUtterance::tag
};

/// The side an utterance tells the human the robot passes it on (as the human sees it):
/// INFORM / REPEAT say it, ASK_* ask the human to move to the other side. kUndefined for the
/// acts that do not say the robot passes (dock family, dock-if-needed, thanks).
Side robotPassingSide(const Utterance& u);
/// The robot makes room: a dock, a wider place, a retreat or a stop is announced.
bool announcesMakingRoom(SpeechAct act);
/// The act ends a stand-off (kInformGoingFirst, kInformResuming): a new plan for the crossing,
/// said after what the group was told this round, not against it.
bool endsStandOff(SpeechAct act);

/// One plan said once per group, and nothing said that contradicts what the robot does.
class CrowdConversation {
 public:
  explicit CrowdConversation(const CrowdConfig& config = {});

  /// One step. `decided`: the utterances the humans' decisions produced at this step, in any
  /// order; `scene`: the humans present now; `robot_making_room`: the robot holds a dock (or a
  /// retreat) for someone after this step's decisions. Returns one entry per decided utterance:
  /// the announcements of making room first (so that this step's passing statements are judged
  /// against them), then by human id.
  std::vector<CoordinatedUtterance> coordinate(const Pose2& robot,
                                               const std::vector<CrowdMember>& scene,
                                               std::vector<DecidedUtterance> decided,
                                               bool robot_making_room);
  /// The human left the scene: what its group was told no longer binds anyone.
  void forget(std::int32_t id);

 private:
  struct Told {
    SpeechAct act;
    Side robot_side;  ///< robotPassingSide of what was said
    std::int32_t said_to;
  };
  CrowdConfig config_;
  /// Per human and round: what it was told (directly or as part of its group).
  std::map<std::pair<std::int32_t, int>, Told> told_;
};

}  // namespace coopnav::dialogue
