#include "coopnav/sim/tracker.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "coopnav/geometry/geometry.hpp"

namespace coopnav::sim {

namespace {

/// Random streams of the tracker: Rng::forStream(seed, kTrackerStream + person id) per person, and
/// kTrackerStream itself for the switch schedule. Person ids are int32 >= 1, so none of these
/// meets a human's own stream (seed, id).
constexpr std::uint64_t kTrackerStream = std::uint64_t{1} << 40;

/// Below this estimated speed a track keeps its heading (as the simulator does for its humans,
/// lib/src/sim/simulation.cpp): the direction of a slow or noisy velocity is noise.
constexpr double kHeadingMinSpeed_m_s = 0.3;

std::string num(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace

bool TrackerParams::active() const {
  return position_sigma_m > 0.0 || miss_probability > 0.0 || id_switches > 0 || range_m > 0.0;
}

std::vector<std::string> TrackerParams::validate() const {
  std::vector<std::string> errors;
  auto check = [&](bool ok, const char* key, double value, const char* allowed) {
    if (!ok)
      errors.push_back(std::string("tracker.") + key + " = " + num(value) + " must be " + allowed);
  };
  check(std::isfinite(position_sigma_m) && position_sigma_m >= 0.0 && position_sigma_m <= 2.0,
        "position_sigma_m", position_sigma_m, "in [0, 2] m");
  check(velocity_window_steps >= 1 && velocity_window_steps <= 100, "velocity_window_steps",
        velocity_window_steps, "an integer in [1, 100]");
  check(std::isfinite(miss_probability) && miss_probability >= 0.0 && miss_probability <= 0.99,
        "miss_probability", miss_probability, "in [0, 0.99]");
  check(std::isfinite(drop_after_s) && drop_after_s >= 0.0 && drop_after_s <= 3600.0,
        "drop_after_s", drop_after_s, "in [0, 3600] s");
  check(id_switches >= 0 && id_switches <= 1000, "id_switches", id_switches,
        "an integer in [0, 1000]");
  check(std::isfinite(id_switch_window_s) && id_switch_window_s >= 0.0 &&
            id_switch_window_s <= 86400.0,
        "id_switch_window_s", id_switch_window_s, "in [0, 86400] s");
  check(std::isfinite(range_m) && range_m >= 0.0 && range_m <= 1e6, "range_m", range_m,
        "in [0, 1e6] m (0 = unlimited)");
  return errors;
}

Tracker::Tracker(const TrackerParams& params, std::uint64_t seed,
                 std::vector<std::int32_t> person_ids, double horizon_s)
    : params_(params) {
  const std::vector<std::string> errors = params.validate();
  if (!errors.empty()) {
    std::string all;
    for (const auto& e : errors) all += (all.empty() ? "" : "; ") + e;
    throw std::invalid_argument(all);
  }
  std::set<std::int32_t> seen;
  for (std::size_t i = 0; i < person_ids.size(); ++i) {
    const std::int32_t id = person_ids[i];
    if (id < 1 || !seen.insert(id).second)
      throw std::invalid_argument("tracker: person id " + std::to_string(id) +
                                  " must be >= 1 and unique");
    Person p;
    p.id = id;
    p.rng = Rng::forStream(seed, kTrackerStream + static_cast<std::uint64_t>(id));
    persons_.push_back(std::move(p));
    person_of_id_[id] = i;
    if (id >= next_id_) next_id_ = id + 1;
  }
  // The switch schedule, drawn once: times uniform in (0, window], persons uniform.
  const double window_s = params.id_switch_window_s > 0.0 ? params.id_switch_window_s : horizon_s;
  if (!persons_.empty() && params.active()) {
    Rng rng = Rng::forStream(seed, kTrackerStream);
    for (int k = 0; k < params.id_switches; ++k) {
      const double t_s = window_s * (1.0 - rng.uniform01());
      const auto person = std::min(
          persons_.size() - 1,
          static_cast<std::size_t>(rng.uniform01() * static_cast<double>(persons_.size())));
      switches_.emplace_back(t_s, person);
    }
    std::stable_sort(switches_.begin(), switches_.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
  }
}

std::int32_t Tracker::newId(std::size_t person) {
  const std::int32_t id = next_id_++;
  person_of_id_[id] = person;
  return id;
}

std::optional<std::size_t> Tracker::personOf(std::int32_t id) const {
  const auto it = person_of_id_.find(id);
  if (it == person_of_id_.end()) return std::nullopt;
  return it->second;
}

std::vector<TrackedHuman> Tracker::observe(double t_s, const AgentState& robot,
                                           const std::vector<AgentState>& humans) {
  if (humans.size() != persons_.size())
    throw std::invalid_argument("tracker: observe() got " + std::to_string(humans.size()) +
                                " humans, constructed for " + std::to_string(persons_.size()));
  std::vector<TrackedHuman> out;
  out.reserve(humans.size());
  if (!params_.active()) {
    for (std::size_t i = 0; i < humans.size(); ++i) out.push_back({humans[i], i});
    stats_.published += static_cast<std::int64_t>(out.size());
    return out;
  }

  // Id switches due by now: from then on the person is a new track under a new id.
  for (; next_switch_ < switches_.size() && switches_[next_switch_].first <= t_s + 1e-9;
       ++next_switch_) {
    Person& p = persons_[switches_[next_switch_].second];
    p.id = newId(switches_[next_switch_].second);
    p.tracked = false;
    p.history.clear();
    ++stats_.switches;
  }

  const Eigen::Vector2d robot_p = robot.pose.position();
  for (std::size_t i = 0; i < humans.size(); ++i) {
    Person& p = persons_[i];
    const AgentState& truth = humans[i];
    // Every draw is made whether or not it is used, so that what one person's stream gives does
    // not depend on the others or on the range.
    const bool missed =
        params_.miss_probability > 0.0 && p.rng.uniform01() < params_.miss_probability;
    Eigen::Vector2d noise{0.0, 0.0};
    if (params_.position_sigma_m > 0.0) {
      noise.x() = p.rng.normal(0.0, params_.position_sigma_m);
      noise.y() = p.rng.normal(0.0, params_.position_sigma_m);
    }
    const bool in_range =
        !(params_.range_m > 0.0) || (truth.pose.position() - robot_p).norm() <= params_.range_m;
    if (!in_range) ++stats_.out_of_range;
    if (missed && in_range) ++stats_.missed;
    if (missed || !in_range) continue;

    if (p.tracked && t_s - p.last_seen_s > params_.drop_after_s + 1e-9) {
      // Lost for too long: the tracker starts a new track for it.
      p.id = newId(i);
      p.tracked = false;
      p.history.clear();
      ++stats_.dropped;
    }
    if (!p.tracked) {
      p.tracked = true;
      p.theta_rad = truth.pose.theta_rad;  // no velocity yet: the body's own heading
    }
    p.last_seen_s = t_s;
    const Eigen::Vector2d pos = truth.pose.position() + noise;
    p.history.push_back({t_s, pos});
    const auto keep = static_cast<std::size_t>(params_.velocity_window_steps) + 1;
    if (p.history.size() > keep)
      p.history.erase(p.history.begin(),
                      p.history.begin() + static_cast<std::ptrdiff_t>(p.history.size() - keep));

    TrackedHuman h;
    h.person = i;
    h.state.id = p.id;
    h.state.kind = AgentKind::kHuman;
    h.state.radius_m = truth.radius_m;
    h.state.pose = {pos.x(), pos.y(), p.theta_rad};
    const Sample& oldest = p.history.front();
    const double span_s = t_s - oldest.t_s;
    Eigen::Vector2d v{0.0, 0.0};
    // A new track has no velocity until its window is full: a difference of two noisy samples
    // 0.1 s apart is noise of ~0.7 m/s at σ 0.05 m, and a heading from it would point anywhere
    // (trackers confirm a track over a few detections before trusting its motion).
    if (p.history.size() >= keep && span_s > 0.0) v = (pos - oldest.p) / span_s;
    const double theta_before = p.theta_rad;
    if (v.norm() >= kHeadingMinSpeed_m_s) p.theta_rad = std::atan2(v.y(), v.x());
    const double dt_s = p.history.size() >= 2 ? t_s - p.history[p.history.size() - 2].t_s : 0.0;
    h.state.pose.theta_rad = p.theta_rad;
    h.state.velocity = {v.x(), v.y(),
                        dt_s > 0.0 ? wrapAngle(p.theta_rad - theta_before) / dt_s : 0.0};
    out.push_back(h);
  }
  stats_.published += static_cast<std::int64_t>(out.size());
  return out;
}

}  // namespace coopnav::sim
