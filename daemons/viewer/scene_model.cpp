#include "scene_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "coopnav/assessment/situation.hpp"
#include "coopnav/channels.hpp"

namespace coopnav::viewer {
namespace {

using nlohmann::json;

/// [m] or [s] as the page reads it: finite numbers rounded to 1e-4 (a tenth of a millimetre;
/// shorter JSON), +inf / -inf as the strings "inf" / "-inf" (a known "nothing within range"),
/// NaN as null (unknown).
json num(double x) {
  if (std::isnan(x)) return nullptr;
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return std::round(x * 1e4) / 1e4;
}
json num(const std::optional<double>& x) { return x ? num(*x) : json(nullptr); }

json point(const Eigen::Vector2d& p) {
  if (!p.allFinite()) return nullptr;
  return json::array({num(p.x()), num(p.y())});
}

double seconds(std::int64_t utime) { return utimeToSeconds(utime); }

json bandJson(const Band& band) {
  json poses = json::array();
  for (const TimedPose& p : band.poses)
    poses.push_back(
        json::array({num(p.t_s), num(p.pose.x_m), num(p.pose.y_m), num(p.pose.theta_rad)}));
  return poses;
}

json agentJson(const AgentState& a) {
  return {{"id", a.id},
          {"x", num(a.pose.x_m)},
          {"y", num(a.pose.y_m)},
          {"theta", num(a.pose.theta_rad)},
          {"vx", num(a.velocity.vx_m_s)},
          {"vy", num(a.velocity.vy_m_s)},
          {"radius", num(a.radius_m)}};
}

const char* tristateName(Tristate t) {
  switch (t) {
    case Tristate::kTrue:
      return "true";
    case Tristate::kFalse:
      return "false";
    default:
      return "unknown";
  }
}

const char* sideName(Side s) {
  switch (s) {
    case Side::kLeft:
      return "left";
    case Side::kRight:
      return "right";
    default:
      return "undefined";
  }
}

const char* recordingName(assessment::RecorderState s) {
  switch (s) {
    case assessment::RecorderState::kRecording:
      return "recording";
    case assessment::RecorderState::kStopped:
      return "stopped";
    default:
      return "idle";
  }
}

const char* statusStateName(std::int8_t s) {
  switch (s) {
    case daemon_status_t::STATE_STARTING:
      return "starting";
    case daemon_status_t::STATE_RUNNING:
      return "running";
    case daemon_status_t::STATE_DEGRADED:
      return "degraded";
    case daemon_status_t::STATE_STOPPING:
      return "stopping";
    default:
      return "unknown";
  }
}

const char* simStateName(std::int8_t s) {
  switch (s) {
    case sim_status_t::STATE_RUNNING:
      return "running";
    case sim_status_t::STATE_GOAL_REACHED:
      return "goal_reached";
    case sim_status_t::STATE_COLLISION:
      return "collision";
    case sim_status_t::STATE_TIME_LIMIT:
      return "time_limit";
    case sim_status_t::STATE_PARTICIPANT_TIMEOUT:
      return "participant_timeout";
    case sim_status_t::STATE_ERROR:
      return "error";
    case sim_status_t::STATE_STANDSTILL:
      return "standstill";
    default:
      return "unknown";
  }
}

const char* guardName(std::int8_t g) {
  switch (g) {
    case velocity_command_t::GUARD_SLOWED:
      return "slowed";
    case velocity_command_t::GUARD_STOPPED:
      return "stopped";
    case velocity_command_t::GUARD_EVADING:
      return "evading";
    default:
      return "none";
  }
}

const char* roomPlanName(std::int8_t r) {
  switch (r) {
    case bands_t::ROOM_DOCK_HERE:
      return "dock_here";
    case bands_t::ROOM_WIDER_PLACE:
      return "wider_place";
    case bands_t::ROOM_RETREAT:
      return "retreat";
    case bands_t::ROOM_NONE:
      return "none";
    default:
      return "unknown";
  }
}

/// The point of `path` nearest to p (p itself for an empty path).
Eigen::Vector2d nearestOnPath(const Path2& path, const Eigen::Vector2d& p) {
  if (path.empty()) return p;
  Eigen::Vector2d best = path.front();
  double best_d2 = (best - p).squaredNorm();
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector2d& a = path[i - 1];
    const Eigen::Vector2d ab = path[i] - a;
    const double len2 = ab.squaredNorm();
    const double s = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const Eigen::Vector2d q = a + s * ab;
    const double d2 = (q - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = q;
    }
  }
  return best;
}

/// A segment [from, to] as JSON, or null when either end is not finite.
json segment(const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  if (!from.allFinite() || !to.allFinite()) return nullptr;
  return json::array({point(from), point(to)});
}

template <class T>
void keepNewest(std::deque<T>& q, int n) {
  while (static_cast<int>(q.size()) > std::max(n, 0)) q.pop_front();
}

}  // namespace

std::string validUtf8(const std::string& text) {
  static constexpr char kReplacement[] = "\xEF\xBF\xBD";
  std::string out;
  out.reserve(text.size());
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const auto cont = [&](std::size_t i) { return i < text.size() && (byte(i) & 0xC0u) == 0x80u; };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char b = byte(i);
    std::size_t len = 0;
    if (b < 0x80u) {
      len = 1;
    } else if (b >= 0xC2u && b <= 0xDFu) {
      len = cont(i + 1) ? 2 : 0;
    } else if (b >= 0xE0u && b <= 0xEFu) {
      // E0: no overlong (second byte >= A0); ED: no surrogates (second byte <= 9F).
      const bool ok = cont(i + 1) && cont(i + 2) && !(b == 0xE0u && byte(i + 1) < 0xA0u) &&
                      !(b == 0xEDu && byte(i + 1) > 0x9Fu);
      len = ok ? 3 : 0;
    } else if (b >= 0xF0u && b <= 0xF4u) {
      // F0: no overlong (>= 90); F4: nothing above U+10FFFF (<= 8F).
      const bool ok = cont(i + 1) && cont(i + 2) && cont(i + 3) &&
                      !(b == 0xF0u && byte(i + 1) < 0x90u) && !(b == 0xF4u && byte(i + 1) > 0x8Fu);
      len = ok ? 4 : 0;
    }
    if (len == 0) {
      out += kReplacement;
      ++i;
    } else {
      out.append(text, i, len);
      i += len;
    }
  }
  return out;
}

std::int64_t SkipCounts::total() const {
  std::int64_t n = 0;
  for (const auto& [channel, count] : rejected) n += count;
  return n;
}

SceneModel::SceneModel(SceneOptions options)
    : options_(options),
      clock_(options_.limits.max_time_jump_s, options_.limits.time_resync_messages) {}

std::string SceneModel::keep(const std::string& text) const {
  return keptText(validUtf8(text), options_.limits.maxTextBytes());
}

void SceneModel::checkTime(std::int64_t utime, const char* what) const {
  const auto now = clock_.now();
  if (!now) return;
  if (std::abs(utimeDiffSeconds(utime, *now)) > options_.limits.max_time_jump_s)
    throw RejectedMessage(std::string(what) + ": " + clock_.describe(utime) +
                          " (over limits.max_time_jump_s)");
}

SceneModel::HumanTrace& SceneModel::trace(std::int32_t id, std::int64_t utime) {
  HumanTrace& t = traces_[id];
  t.last_utime = std::max(t.last_utime, utime);
  return t;
}

void SceneModel::forgetOld() {
  // Ageing needs the scene's time; the caps below hold before the first agent states too.
  if (const auto now = clock_.now()) {
    const auto old = [&](std::int64_t u) {
      return utimeDiffSeconds(*now, u) > options_.limits.forget_after_s;
    };
    for (auto it = traces_.begin(); it != traces_.end();)
      it = old(it->second.last_utime) ? traces_.erase(it) : std::next(it);
    for (auto it = situations_.begin(); it != situations_.end();)
      it = old(it->second.utime) ? situations_.erase(it) : std::next(it);
    for (auto it = references_.begin(); it != references_.end();)
      it = old(it->second.utime) ? references_.erase(it) : std::next(it);
  }
  // Beyond max_ids humans, the least recently heard go first.
  const auto max_ids = static_cast<std::size_t>(options_.limits.max_ids);
  while (traces_.size() > max_ids) {
    auto oldest = std::min_element(
        traces_.begin(), traces_.end(),
        [](const auto& a, const auto& b) { return a.second.last_utime < b.second.last_utime; });
    traces_.erase(oldest);
  }
  while (situations_.size() > max_ids) {
    auto oldest = std::min_element(
        situations_.begin(), situations_.end(),
        [](const auto& a, const auto& b) { return a.second.utime < b.second.utime; });
    situations_.erase(oldest);
  }
  while (references_.size() > max_ids) {
    auto oldest = std::min_element(
        references_.begin(), references_.end(),
        [](const auto& a, const auto& b) { return a.second.utime < b.second.utime; });
    references_.erase(oldest);
  }
}

void SceneModel::apply(const agent_states_t& msg) {
  AgentStatesSnapshot s = fromLcm(msg);  // throws RejectedMessage (NaN, counts, ids)
  // A resync is a new run (or a restarted simulator): what was drawn belongs to the old time line.
  if (!clock_.take(s.utime, "agent states", [&] { newTimeLine(); }))
    throw DroppedMessage("agent states: older than the scene");
  states_ = std::move(s);
  forgetOld();
}

void SceneModel::newTimeLine() {
  states_.reset();
  bands_.reset();
  references_.clear();
  situations_.clear();
  traces_.clear();
  utterances_.clear();
  actions_.clear();
  command_.reset();
  goals_.reset();
  sim_.reset();
}

void SceneModel::apply(const bands_t& msg) {
  BandsSnapshot b = fromLcm(msg);
  // The wire keeps a band with NaN (the assessors call that human's crossing unknown); a band
  // that cannot be drawn is skipped and counted here.
  const auto finite = [](const Band& band) {
    return std::all_of(band.poses.begin(), band.poses.end(), [](const TimedPose& p) {
      return std::isfinite(p.t_s) && std::isfinite(p.pose.x_m) && std::isfinite(p.pose.y_m) &&
             std::isfinite(p.pose.theta_rad);
    });
  };
  if (!finite(b.robot)) throw RejectedMessage("bands: the robot band is not finite");
  for (const auto& [id, band] : b.humans)
    if (!finite(band))
      throw RejectedMessage("bands: the band of human " + std::to_string(id) + " is not finite");
  checkTime(b.utime, "bands");
  b.robot.poses = decimated(std::move(b.robot.poses), options_.max_polyline_points);
  for (auto& [id, band] : b.humans)
    band.poses = decimated(std::move(band.poses), options_.max_polyline_points);
  bands_ = std::move(b);
}

void SceneModel::apply(const reference_paths_t& msg) {
  ReferencePaths r = fromLcm(msg);
  checkTime(r.utime, "reference paths");
  for (auto& e : r.paths) {
    if (e.path.empty()) continue;  // an empty path keeps the previous one (as the assessors)
    e.path = decimated(std::move(e.path), options_.max_polyline_points);
    const std::int32_t id = e.agent_id;
    references_[id] = {r.utime, std::move(e)};
  }
  forgetOld();
}

void SceneModel::apply(const situation_t& msg) {
  SituationRecord r = fromLcm(msg);
  checkTime(r.utime, "situation");
  r.assessment.reason = keep(r.assessment.reason);
  r.crossing.reason = keep(r.crossing.reason);
  situations_[r.human_id] = std::move(r);
  forgetOld();
}

void SceneModel::apply(const path_assessment_t& msg) {
  PathAssessmentRecord r = fromLcm(msg);
  checkTime(r.utime, "path assessment");
  r.profile = keep(r.profile);
  HumanTrace& t = trace(r.human_id, r.utime);
  // The CA window on the plot's time axis (its samples are sample_period_s apart, the newest at
  // the message's time), then decimated.
  {
    const double t_s = seconds(r.utime);
    const std::size_t n = r.window_ca_m.size();
    std::vector<std::pair<double, double>> ca;
    ca.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
      ca.emplace_back(t_s - static_cast<double>(n - 1 - i) * options_.ca_sample_period_s,
                      r.window_ca_m[i]);
    t.ca = decimated(std::move(ca), options_.max_polyline_points);
    r.window_ca_m.clear();
    r.window_ca_m.shrink_to_fit();
  }
  if (r.snapshot.cm_window_m) {
    const double ts = seconds(r.utime);
    // A repeat of a step (lockstep retransmission) or a reordered one replaces, never duplicates.
    while (!t.cm.empty() && t.cm.back().first >= ts) t.cm.pop_back();
    t.cm.emplace_back(ts, *r.snapshot.cm_window_m);
    while (static_cast<int>(t.cm.size()) > options_.cm_history_points) t.cm.pop_front();
  }
  if (r.p_contributing) {
    const double ts = seconds(r.utime);
    // Bounded and de-duplicated as CM's history.
    auto& p = t.p_contributing;
    while (!p.empty() && p.back().first >= ts) p.pop_back();
    p.emplace_back(ts, *r.p_contributing);
    while (static_cast<int>(p.size()) > options_.cm_history_points) p.pop_front();
  }
  t.assessment = std::move(r);
  forgetOld();
}

void SceneModel::apply(const path_assessor_control_t& msg) {
  RecorderControl c = fromLcm(msg);
  checkTime(c.utime, "path assessor control");
  HumanTrace& t = trace(c.human_id, c.utime);
  t.controls.emplace_back(seconds(c.utime), dialogue::toString(c.command));
  if (static_cast<int>(t.controls.size()) > options_.max_utterances)
    t.controls.erase(t.controls.begin());
  forgetOld();
}

void SceneModel::apply(const utterance_t& msg) {
  UtteranceMsg u = fromLcm(msg);
  checkTime(u.stamp.utime, "utterance");
  u.utterance.text = keep(u.utterance.text);
  utterances_.push_back(std::move(u));
  keepNewest(utterances_, options_.max_utterances);
}

void SceneModel::apply(const robot_action_t& msg) {
  RobotActionMsg a = fromLcm(msg);
  checkTime(a.stamp.utime, "robot action");
  a.reason = keep(a.reason);
  actions_.push_back(std::move(a));
  keepNewest(actions_, options_.max_utterances);
}

void SceneModel::apply(const velocity_command_t& msg) {
  VelocityCommand c = fromLcm(msg);
  if (!std::isfinite(c.body.vx_m_s) || !std::isfinite(c.body.vy_m_s) ||
      !std::isfinite(c.body.omega_rad_s))
    throw RejectedMessage("velocity command: non-finite velocity");
  checkTime(c.utime, "velocity command");
  command_ = c;
}

void SceneModel::apply(const goals_t& msg) {
  GoalsSnapshot g = fromLcm(msg);
  checkTime(g.utime, "goals");
  goals_ = std::move(g);
}

void SceneModel::apply(const daemon_status_t& msg, std::int64_t received_utime) {
  // Statuses have no lib type: checked here. NaN cycle times are "none" (allowed).
  if (msg.name.empty() || msg.name.size() > 64)
    throw RejectedMessage("daemon status: name empty or over 64 bytes");
  if (msg.state < daemon_status_t::STATE_STARTING || msg.state > daemon_status_t::STATE_STOPPING)
    throw RejectedMessage("daemon status: unknown state " + std::to_string(msg.state));
  // The stamp against the receive clock: far before it is a forged (or broken) clock; after it,
  // the status counts as received now, so no stamp can make the others look old.
  if (utimeDiffSeconds(received_utime, msg.utime) > options_.limits.max_time_jump_s)
    throw RejectedMessage("daemon status: stamp " + std::to_string(msg.utime) +
                          " over limits.max_time_jump_s before its receive time " +
                          std::to_string(received_utime));
  const std::int64_t stamp = std::min(msg.utime, received_utime);
  const std::string name = validUtf8(msg.name);
  // Full table, new name: the stalest entry goes (a forged name that stopped being sent goes
  // before a daemon that reports every second; the newcomer is never the one refused).
  if (!statuses_.count(name)) {
    while (!statuses_.empty() &&
           statuses_.size() >= static_cast<std::size_t>(options_.limits.max_ids)) {
      statuses_.erase(std::min_element(
          statuses_.begin(), statuses_.end(),
          [](const auto& a, const auto& b) { return a.second.stamp < b.second.stamp; }));
    }
  }
  StatusEntry kept{msg, stamp};
  kept.msg.name = name;
  kept.msg.detail = keep(msg.detail);
  newest_status_utime_ = std::max(newest_status_utime_, stamp);
  statuses_[name] = std::move(kept);
  // Daemons not heard for limits.forget_after_s of the status clock are forgotten.
  for (auto it = statuses_.begin(); it != statuses_.end();)
    it = utimeDiffSeconds(newest_status_utime_, it->second.stamp) > options_.limits.forget_after_s
             ? statuses_.erase(it)
             : std::next(it);
}

void SceneModel::apply(const sim_status_t& msg) {
  if (msg.state < sim_status_t::STATE_RUNNING || msg.state > sim_status_t::STATE_STANDSTILL)
    throw RejectedMessage("sim status: unknown state " + std::to_string(msg.state));
  if (!std::isfinite(msg.min_clearance_m) && !std::isinf(msg.min_clearance_m))
    throw RejectedMessage("sim status: min_clearance_m is NaN");
  checkTime(msg.utime, "sim status");
  sim_ = msg;
  sim_->scenario = keep(msg.scenario);
  sim_->detail = keep(msg.detail);
}

namespace {
template <class Msg>
void decodeAndApply(SceneModel& scene, const void* data, std::size_t size) {
  Msg msg;
  decodeOrReject(data, size, msg);
  scene.apply(msg);
}
}  // namespace

bool SceneModel::applyRaw(const std::string& channel, const void* data, std::size_t size,
                          std::int64_t received_utime) {
  namespace ch = channels;
  if (channel == ch::kAgentStates) {
    decodeAndApply<agent_states_t>(*this, data, size);
  } else if (channel == ch::kBands) {
    decodeAndApply<bands_t>(*this, data, size);
  } else if (channel == ch::kReferencePaths) {
    decodeAndApply<reference_paths_t>(*this, data, size);
  } else if (channel == ch::kSituation) {
    decodeAndApply<situation_t>(*this, data, size);
  } else if (channel == ch::kPathAssessment) {
    decodeAndApply<path_assessment_t>(*this, data, size);
  } else if (channel == ch::kPathAssessorControl) {
    decodeAndApply<path_assessor_control_t>(*this, data, size);
  } else if (channel == ch::kUtterance) {
    decodeAndApply<utterance_t>(*this, data, size);
  } else if (channel == ch::kRobotAction) {
    decodeAndApply<robot_action_t>(*this, data, size);
  } else if (channel == ch::kRobotCmd) {
    decodeAndApply<velocity_command_t>(*this, data, size);
  } else if (channel == ch::kGoals) {
    decodeAndApply<goals_t>(*this, data, size);
  } else if (channel == ch::kStatus) {
    daemon_status_t msg;
    decodeOrReject(data, size, msg);
    apply(msg, received_utime);
  } else if (channel == ch::kSimStatus) {
    decodeAndApply<sim_status_t>(*this, data, size);
  } else {
    return false;
  }
  return true;
}

json SceneModel::situationJson(const SituationRecord& s) const {
  const assessment::CrossingInfo& c = s.crossing;
  const assessment::SituationAssessment& a = s.assessment;
  json j = {{"human_id", s.human_id},
            {"t", seconds(s.utime)},
            {"step", s.step},
            {"crossing", assessment::toString(c.status)},
            {"has_reference", s.has_reference},
            {"t_cross_s", num(c.t_cross_s)},
            {"t_cross_at", c.t_cross_s ? num(seconds(s.utime) + *c.t_cross_s) : json(nullptr)},
            {"cp_h", point(c.cp_h)},
            {"cp_r", point(c.cp_r)},
            {"dir", sideName(c.dir)},
            {"d_h_m", num(a.d_h_m)},
            {"d_oh_m", num(a.d_oh_m)},
            {"d_or_m", num(a.d_or_m)},
            {"d_hr_m", num(a.d_hr_m)},
            {"predicates",
             {{"human_needs_to_contribute", tristateName(a.human_needs_to_contribute)},
              {"human_is_constrained", tristateName(a.human_is_constrained)},
              {"robot_is_constrained", tristateName(a.robot_is_constrained)}}},
            {"tau",
             {{"h", num(s.thresholds.tau_h_m)},
              {"oh", num(s.thresholds.tau_oh_m)},
              {"or", num(s.thresholds.tau_or_m)},
              {"hr", num(s.thresholds.tau_hr_m)}}},
            {"room_plan", roomPlanName(s.room_plan)},
            {"robot_mode", commandModeName(s.robot_mode)},
            {"reason", a.reason.empty() ? c.reason : a.reason}};
  // The distances as segments: where each was measured (paper §II-B, design-readings).
  json seg = {{"d_h", nullptr}, {"d_oh", nullptr}, {"d_or", nullptr}, {"d_hr", nullptr}};
  if (c.status == assessment::CrossingStatus::kOk && c.cp_h.allFinite() && c.cp_r.allFinite()) {
    seg["d_hr"] = segment(c.cp_h, c.cp_r);
    const auto ref = references_.find(s.human_id);
    if (a.d_h_m && ref != references_.end())
      seg["d_h"] = segment(c.cp_h, nearestOnPath(ref->second.entry.path, c.cp_h));
    const auto q = assessment::halfPlaneQueries(c, s.thresholds);
    const auto obstacleEnd = [&](const assessment::HalfPlaneQuery& hq,
                                 const std::optional<double>& d, double radius) -> json {
      if (!d || !std::isfinite(*d)) return nullptr;
      if (map_) {
        const DistanceResult r = map_->nearestInHalfPlane(hq.point, hq.normal, *d + radius + 1.0);
        if (r.status == DistanceStatus::kOk) return segment(hq.point, r.obstacle);
      }
      return segment(hq.point, hq.point + (*d + radius) * hq.normal.normalized());
    };
    if (q) {
      seg["d_oh"] = obstacleEnd(q->human, a.d_oh_m, s.thresholds.human_radius_m);
      seg["d_or"] = obstacleEnd(q->robot, a.d_or_m, s.thresholds.robot_radius_m);
    }
  }
  j["segments"] = std::move(seg);
  return j;
}

json SceneModel::toJson() const {
  json j;
  const auto now = clock_.now();
  const double t_now = now ? seconds(*now) : std::numeric_limits<double>::quiet_NaN();
  j["utime"] = now ? json(*now) : json(nullptr);
  j["t"] = num(t_now);
  j["step"] = states_ ? states_->step : -1;

  // Agents and the robot's mode (the band source's command; its bands' mode before any).
  if (states_) {
    json robot = agentJson(states_->robot);
    std::int8_t mode = bands_ ? bands_->robot_mode : velocity_command_t::MODE_IDLE;
    if (command_) mode = command_->mode;
    robot["mode"] = commandModeName(mode);
    robot["guard"] = command_ ? guardName(command_->guard) : "none";
    j["robot"] = std::move(robot);
    json humans = json::array();
    for (const AgentState& h : states_->humans) humans.push_back(agentJson(h));
    j["humans"] = std::move(humans);
  } else {
    j["robot"] = nullptr;
    j["humans"] = json::array();
  }

  json goals = json::array();
  if (goals_) {
    for (const Goal& g : goals_->goals)
      goals.push_back({{"id", g.agent_id},
                       {"kind", g.kind == AgentKind::kRobot ? "robot" : "human"},
                       {"x", num(g.pose.x_m)},
                       {"y", num(g.pose.y_m)}});
  }
  j["goals"] = std::move(goals);

  if (bands_) {
    json humans = json::array();
    for (std::size_t i = 0; i < bands_->humans.size(); ++i) {
      const auto& [id, band] = bands_->humans[i];
      humans.push_back({{"id", id},
                        {"room_plan", roomPlanName(bands_->roomPlan(id))},
                        {"poses", bandJson(band)}});
    }
    j["bands"] = {{"t", seconds(bands_->utime)},
                  {"status", static_cast<int>(bands_->status)},
                  {"robot_mode", commandModeName(bands_->robot_mode)},
                  {"robot", bandJson(bands_->robot)},
                  {"humans", std::move(humans)}};
  } else {
    j["bands"] = nullptr;
  }

  json refs = json::array();
  for (const auto& [id, r] : references_) {
    json pts = json::array();
    for (const Eigen::Vector2d& p : r.entry.path) pts.push_back(point(p));
    refs.push_back({{"id", id}, {"revision", r.entry.revision}, {"points", std::move(pts)}});
  }
  j["reference_paths"] = std::move(refs);

  json situations = json::array();
  for (const auto& [id, s] : situations_) situations.push_back(situationJson(s));
  j["situations"] = std::move(situations);

  // Utterances: a bubble by the robot from when speaking starts until bubble_hold_s after it ends.
  json utterances = json::array();
  for (const UtteranceMsg& u : utterances_) {
    const double t = seconds(u.stamp.utime);
    const double from = t + u.slot.start_s;
    const double until = from + u.slot.duration_s + options_.bubble_hold_s;
    utterances.push_back({{"t", num(t)},
                          {"human_id", u.stamp.human_id},
                          {"act", dialogue::toString(u.utterance.act)},
                          {"direction", sideName(u.utterance.direction)},
                          {"round", u.utterance.round},
                          {"text", u.utterance.text},
                          {"delivery", dialogue::toString(u.slot.delivery)},
                          {"speech_start_s", num(u.slot.start_s)},
                          {"speech_duration_s", num(u.slot.duration_s)},
                          {"group_ids", u.group},
                          {"show_from", num(from)},
                          {"show_until", num(until)},
                          {"active", now.has_value() && t_now >= t && t_now <= until}});
  }
  j["utterances"] = std::move(utterances);

  json actions = json::array();
  for (const RobotActionMsg& a : actions_)
    actions.push_back({{"t", num(seconds(a.stamp.utime))},
                       {"human_id", a.stamp.human_id},
                       {"action", dialogue::toString(a.action)},
                       {"reason", a.reason}});
  j["actions"] = std::move(actions);

  // Per human: the CA window, CM over time, τ and the round markers.
  json assessments = json::array();
  for (const auto& [id, tr] : traces_) {
    json a = {{"human_id", id}};
    if (tr.assessment) {
      const PathAssessmentRecord& r = *tr.assessment;
      const double t = seconds(r.utime);
      json ca = json::array();
      for (const auto& [ts, v] : tr.ca) ca.push_back(json::array({num(ts), num(v)}));
      a["t"] = num(t);
      a["recording"] = recordingName(r.snapshot.state);
      a["ca"] = std::move(ca);
      a["cm_m"] = num(r.snapshot.cm_window_m);
      a["is_contributing"] = tristateName(r.snapshot.is_contributing_window);
      a["cm_interaction_m"] = num(r.snapshot.cm_interaction_m);
      a["p_contributing"] = num(r.p_contributing);
      a["tau_m"] = num(r.snapshot.tau_m);
      a["gamma"] = num(r.gamma);
      a["profile"] = r.profile;
    } else {
      a["recording"] = "idle";
      a["ca"] = json::array();
      a["cm_m"] = nullptr;
      a["p_contributing"] = nullptr;
      a["tau_m"] = nullptr;
      a["is_contributing"] = "unknown";
    }
    json cm = json::array();
    for (const auto& [t, v] : tr.cm) cm.push_back(json::array({num(t), num(v)}));
    a["cm_history"] = std::move(cm);
    json pc = json::array();
    for (const auto& [t, v] : tr.p_contributing) pc.push_back(json::array({num(t), num(v)}));
    a["p_contributing_history"] = std::move(pc);
    json controls = json::array();
    for (const auto& [t, what] : tr.controls) controls.push_back(json::array({num(t), what}));
    a["controls"] = std::move(controls);
    json rounds = json::array();
    for (const UtteranceMsg& u : utterances_) {
      const bool to_this =
          u.stamp.human_id == id || std::find(u.group.begin(), u.group.end(), id) != u.group.end();
      if (to_this)
        rounds.push_back(json::array(
            {num(seconds(u.stamp.utime)), u.utterance.round, dialogue::toString(u.utterance.act)}));
    }
    for (const RobotActionMsg& act : actions_)
      if (act.stamp.human_id == id)
        rounds.push_back(
            json::array({num(seconds(act.stamp.utime)), 2, dialogue::toString(act.action)}));
    a["rounds"] = std::move(rounds);
    assessments.push_back(std::move(a));
  }
  j["assessments"] = std::move(assessments);

  json statuses = json::array();
  for (const auto& [name, e] : statuses_) {
    const daemon_status_t& s = e.msg;
    const double age = utimeDiffSeconds(newest_status_utime_, e.stamp);
    statuses.push_back({{"name", name},
                        {"pid", s.pid},
                        {"state", statusStateName(s.state)},
                        {"received", s.received},
                        {"dropped", s.dropped},
                        {"rejected", s.rejected},
                        {"published", s.published},
                        {"cycle_p50_ms", num(s.cycle_p50_ms)},
                        {"cycle_max_ms", num(s.cycle_max_ms)},
                        {"backlog", s.backlog},
                        {"detail", s.detail},
                        {"age_s", num(age)},
                        {"silent", age > options_.status_stale_s}});
  }
  j["statuses"] = std::move(statuses);

  if (sim_) {
    j["sim"] = {{"t", num(seconds(sim_->utime))},
                {"step", sim_->step},
                {"state", simStateName(sim_->state)},
                {"scenario", sim_->scenario},
                {"min_clearance_m", num(sim_->min_clearance_m)},
                {"robot_time_to_goal_s", num(sim_->robot_time_to_goal_s)},
                {"contact", static_cast<int>(sim_->contact)},
                {"detail", sim_->detail}};
  } else {
    j["sim"] = nullptr;
  }

  json skipped = json::object();
  for (const auto& [channel, n] : skipped_.rejected) skipped[channel] = n;
  j["viewer"] = {{"skipped", std::move(skipped)}, {"skipped_total", skipped_.total()}};
  return j;
}

}  // namespace coopnav::viewer
