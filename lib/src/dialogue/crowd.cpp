#include "coopnav/dialogue/crowd.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <numeric>

namespace coopnav::dialogue {

std::vector<std::vector<std::int32_t>> findGroups(const std::vector<CrowdMember>& scene,
                                                  const CrowdConfig& config) {
  // Union-find over the links; n is a crowd (tens), so the pairwise pass is cheap.
  const std::size_t n = scene.size();
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const bool near =
          (scene[i].position_m - scene[j].position_m).norm() <= config.group_distance_m;
      const bool alike =
          (scene[i].velocity_m_s - scene[j].velocity_m_s).norm() <= config.group_velocity_diff_m_s;
      if (near && alike) parent[root(i)] = root(j);
    }
  std::map<std::size_t, std::vector<std::int32_t>> by_root;
  for (std::size_t i = 0; i < n; ++i) by_root[root(i)].push_back(scene[i].id);
  std::vector<std::vector<std::int32_t>> groups;
  for (auto& [r, ids] : by_root) {
    std::sort(ids.begin(), ids.end());
    groups.push_back(std::move(ids));
  }
  std::sort(groups.begin(), groups.end(),
            [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return groups;
}

std::string addressPhrase(const Pose2& robot, const std::vector<Eigen::Vector2d>& addressees_m,
                          const CrowdConfig& config) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& p : addressees_m) centroid += p;
  if (!addressees_m.empty()) centroid /= static_cast<double>(addressees_m.size());
  const Eigen::Vector2d d = centroid - robot.position();
  const double bearing =
      std::remainder(std::atan2(d.y(), d.x()) - robot.theta_rad, 2.0 * 3.14159265358979323846);
  const char* where = std::abs(bearing) <= config.ahead_half_angle_rad ? "ahead"
                      : bearing > 0.0                                  ? "on my left"
                                                                       : "on my right";
  static const char* const kCount[] = {"", "", "two", "three", "four", "five"};
  const std::size_t n = addressees_m.size();
  if (n <= 1) return std::string("You ") + where;
  if (n <= 5) return std::string("You ") + kCount[n] + " " + where;
  return std::string("All of you ") + where;
}

const char* toString(CrowdVerdict v) {
  switch (v) {
    case CrowdVerdict::kSay:
      return "say";
    case CrowdVerdict::kToldToGroup:
      return "told_to_group";
    case CrowdVerdict::kContradicts:
      return "contradicts";
  }
  return "?";
}

Side robotPassingSide(const Utterance& u) {
  switch (u.act) {
    case SpeechAct::kInformDirection:
    case SpeechAct::kRepeatDirection:
      return u.direction;
    case SpeechAct::kAskToMove:
    case SpeechAct::kAskToMoveMore:
      return opposite(u.direction);
    default:
      return Side::kUndefined;
  }
}

bool announcesMakingRoom(SpeechAct act) {
  switch (act) {
    case SpeechAct::kInformDocking:
    case SpeechAct::kInformWiderPlace:
    case SpeechAct::kInformRetreat:
    case SpeechAct::kInformStopping:
      return true;
    default:
      return false;
  }
}

bool endsStandOff(SpeechAct act) {
  return act == SpeechAct::kInformGoingFirst || act == SpeechAct::kInformResuming;
}

CrowdConversation::CrowdConversation(const CrowdConfig& config) : config_(config) {}

std::vector<CoordinatedUtterance> CrowdConversation::coordinate(
    const Pose2& robot, const std::vector<CrowdMember>& scene,
    std::vector<DecidedUtterance> decided, bool robot_making_room) {
  std::stable_sort(decided.begin(), decided.end(), [](const auto& a, const auto& b) {
    const bool ra = announcesMakingRoom(a.utterance.act);
    const bool rb = announcesMakingRoom(b.utterance.act);
    return ra != rb ? ra : a.human_id < b.human_id;
  });
  const auto groups = findGroups(scene, config_);
  std::map<std::int32_t, Eigen::Vector2d> where;
  for (const auto& m : scene) where[m.id] = m.position_m;

  std::vector<CoordinatedUtterance> out;
  for (const DecidedUtterance& d : decided) {
    CoordinatedUtterance c{d.human_id, d.utterance, CrowdVerdict::kSay, {}, "", d.tag};
    for (const auto& g : groups)
      if (std::find(g.begin(), g.end(), d.human_id) != g.end())
        for (const auto id : g)
          if (id != d.human_id) c.group.push_back(id);
    const int round = d.utterance.round;
    const Side side = robotPassingSide(d.utterance);
    // What this human's group was already told this round (the human itself first).
    const Told* before = nullptr;
    if (auto it = told_.find({d.human_id, round}); it != told_.end()) before = &it->second;
    for (const auto id : c.group) {
      if (before) break;
      if (auto it = told_.find({id, round}); it != told_.end()) before = &it->second;
    }
    if (robot_making_room && side != Side::kUndefined) {
      c.verdict = CrowdVerdict::kContradicts;
      c.reason = "the robot is making room for someone: it tells nobody that it passes";
    } else if (before) {
      // The same plan: the same side for the robot when either says one (an INFORM and an ASK
      // of the same side agree; two INFORMs of opposite sides part the group), else the same act.
      const bool sided = side != Side::kUndefined || before->robot_side != Side::kUndefined;
      const bool same = sided ? side == before->robot_side : before->act == d.utterance.act;
      if (same) {
        c.verdict = CrowdVerdict::kToldToGroup;
        c.reason = "said to the group in the words to human " + std::to_string(before->said_to);
      } else if (!announcesMakingRoom(d.utterance.act) && !endsStandOff(d.utterance.act)) {
        c.verdict = CrowdVerdict::kContradicts;
        c.reason = std::string("the group was told ") + toString(before->act) +
                   " in the words to human " + std::to_string(before->said_to);
      }
    }
    if (c.verdict == CrowdVerdict::kSay) {
      const Told told{d.utterance.act, side, d.human_id};
      told_[{d.human_id, round}] = told;
      for (const auto id : c.group) told_[{id, round}] = told;
      if (scene.size() > 1) {
        std::vector<Eigen::Vector2d> addressees;
        if (auto it = where.find(d.human_id); it != where.end()) addressees.push_back(it->second);
        for (const auto id : c.group) addressees.push_back(where.at(id));
        if (!addressees.empty()) {
          std::string& text = c.utterance.text;
          // "You on my left, i will ..." would be wrong: keep the sentence's own capital "I".
          if (!text.empty() && !(text[0] == 'I' && (text.size() == 1 || text[1] == ' ')))
            text[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(text[0])));
          text = addressPhrase(robot, addressees, config_) + ", " + text;
        }
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

void CrowdConversation::forget(std::int32_t id) {
  told_.erase(told_.lower_bound({id, std::numeric_limits<int>::min()}),
              told_.upper_bound({id, std::numeric_limits<int>::max()}));
}

}  // namespace coopnav::dialogue
