#include "coopnav/metrics/run_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace coopnav::metrics {
namespace {

double wrapAngle(double a) { return std::remainder(a, 2.0 * M_PI); }

/// Time each frame stands for: from its time to the next frame's (the last frame: none), so that
/// the times of a run add up to its duration whatever the sampling.
std::vector<double> holdTimes(const std::vector<Frame>& frames) {
  std::vector<double> dt(frames.size(), 0.0);
  for (std::size_t k = 0; k + 1 < frames.size(); ++k) dt[k] = frames[k + 1].t_s - frames[k].t_s;
  return dt;
}

void accumulate(Stat3& s, double x, double w, double& w_sum, double& x_sum) {
  if (!std::isfinite(x)) return;
  s.min = std::isnan(s.min) ? x : std::min(s.min, x);
  s.max = std::isnan(s.max) ? x : std::max(s.max, x);
  w_sum += w;
  x_sum += w * x;
}

/// Zone of a gap: 0 intimate, 1 personal, 2 social, 3 public.
int zoneOf(double gap, const MetricsOptions& o) {
  if (gap < o.intimate_m) return 0;
  if (gap < o.personal_m) return 1;
  if (gap < o.social_m) return 2;
  return 3;
}

/// Closing speed of a onto b: a's velocity along the direction from a to b (> 0 closing).
double closingSpeed(const AgentSample& a, const AgentSample& b) {
  const Eigen::Vector2d d = b.p_m - a.p_m;
  const double n = d.norm();
  return n > 0.0 ? a.v_m_s.dot(d / n) : 0.0;
}

}  // namespace

double surfaceGap(const AgentSample& a, const AgentSample& b) {
  return (a.p_m - b.p_m).norm() - a.radius_m - b.radius_m;
}

double timeToCollision(const AgentSample& a, const AgentSample& b, double horizon_s) {
  // |dp + dv t| = R: (dv·dv) t² + 2 (dp·dv) t + (dp·dp - R²) = 0, smallest root >= 0.
  const Eigen::Vector2d dp = b.p_m - a.p_m;
  const Eigen::Vector2d dv = b.v_m_s - a.v_m_s;
  const double r = a.radius_m + b.radius_m;
  const double c = dp.squaredNorm() - r * r;
  if (c <= 0.0) return 0.0;
  const double qa = dv.squaredNorm();
  const double qb = dp.dot(dv);
  if (qa <= 0.0 || qb >= 0.0) return kNaN;  // not closing
  const double disc = qb * qb - qa * c;
  if (disc < 0.0) return kNaN;  // passing wide
  const double t = (-qb - std::sqrt(disc)) / qa;
  return t <= horizon_s ? t : kNaN;
}

double pathLength(const std::vector<Eigen::Vector2d>& points) {
  double l = 0.0;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) l += (points[k + 1] - points[k]).norm();
  return l;
}

double cumulativeHeadingChange(const std::vector<double>& headings_rad) {
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < headings_rad.size(); ++k)
    sum += std::abs(wrapAngle(headings_rad[k + 1] - headings_rad[k]));
  return sum;
}

double pathIrregularity(const std::vector<Eigen::Vector2d>& points, double initial_heading_rad,
                        const Eigen::Vector2d& goal, double min_motion_m) {
  if (points.empty()) return kNaN;
  double turned = 0.0;
  double phi = initial_heading_rad;
  // Directions between points at least min_motion_m apart (standing still has no direction;
  // jitter of a stopped robot would otherwise add turns).
  Eigen::Vector2d from = points.front();
  for (std::size_t k = 1; k < points.size(); ++k) {
    const Eigen::Vector2d d = points[k] - from;
    if (d.norm() < min_motion_m) continue;
    const double next = std::atan2(d.y(), d.x());
    turned += std::abs(wrapAngle(next - phi));
    phi = next;
    from = points[k];
  }
  const Eigen::Vector2d to_goal = goal - points.front();
  const double needed =
      to_goal.norm() > 0.0
          ? std::abs(wrapAngle(std::atan2(to_goal.y(), to_goal.x()) - initial_heading_rad))
          : 0.0;
  return std::max(0.0, turned - needed);
}

double personalSpaceCost(const AgentSample& robot, const AgentSample& person,
                         const MetricsOptions& o) {
  const double speed = person.v_m_s.norm();
  // Still (below a creep of 1 cm/s): the person's heading gives the front.
  const Eigen::Vector2d u =
      speed > 0.01 ? Eigen::Vector2d(person.v_m_s / speed)
                   : Eigen::Vector2d(std::cos(person.theta_rad), std::sin(person.theta_rad));
  const Eigen::Vector2d n{-u.y(), u.x()};
  const Eigen::Vector2d d = robot.p_m - person.p_m;
  const double ahead = d.dot(u);
  const double side = d.dot(n);
  const double sigma_front =
      std::max(o.personal_space_front_s * speed, o.personal_space_min_sigma_m);
  const double sigma_along = ahead > 0.0 ? sigma_front : sigma_front / 3.0;
  const double sigma_side = sigma_front / 4.0;
  return std::exp(-ahead * ahead / (2.0 * sigma_along * sigma_along) -
                  side * side / (2.0 * sigma_side * sigma_side));
}

double longestNoProgress(const std::vector<double>& t_s, const std::vector<double>& distance_m,
                         double progress_m) {
  const std::size_t n = std::min(t_s.size(), distance_m.size());
  if (n == 0) return kNaN;
  // best[k]: the nearest the robot had come by frame k (non-increasing). A span [a, b] made no
  // progress when best[b] > best[a] - progress_m; for each a the longest b is monotone in a.
  std::vector<double> best(n);
  for (std::size_t k = 0; k < n; ++k)
    best[k] = k == 0 ? distance_m[0] : std::min(best[k - 1], distance_m[k]);
  double longest = 0.0;
  std::size_t b = 0;
  for (std::size_t a = 0; a < n; ++a) {
    b = std::max(b, a);
    while (b + 1 < n && best[b + 1] > best[a] - progress_m) ++b;
    longest = std::max(longest, t_s[b] - t_s[a]);
  }
  return longest;
}

Stat3 derivativeStats(const std::vector<double>& t_s, const std::vector<Eigen::Vector2d>& v,
                      int order) {
  std::vector<double> t = t_s;
  std::vector<Eigen::Vector2d> x = v;
  for (int i = 0; i < order; ++i) {
    std::vector<double> tn;
    std::vector<Eigen::Vector2d> xn;
    for (std::size_t k = 0; k + 1 < x.size(); ++k) {
      const double dt = t[k + 1] - t[k];
      if (!(dt > 0.0)) continue;
      tn.push_back(0.5 * (t[k] + t[k + 1]));
      xn.push_back((x[k + 1] - x[k]) / dt);
    }
    t = std::move(tn);
    x = std::move(xn);
  }
  Stat3 s;
  double w_sum = 0.0;
  double x_sum = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    // Each value stands for the time between its neighbours' midpoints (time-weighted mean).
    const double lo = k == 0 ? t[k] : 0.5 * (t[k - 1] + t[k]);
    const double hi = k + 1 == x.size() ? t[k] : 0.5 * (t[k] + t[k + 1]);
    const double w = x.size() == 1 ? 1.0 : hi - lo;
    accumulate(s, x[k].norm(), w, w_sum, x_sum);
  }
  if (w_sum > 0.0) s.avg = x_sum / w_sum;
  return s;
}

double conflictIntensity(const AgentSample& robot, const AgentSample& person,
                         const MetricsOptions& o) {
  const Eigen::Vector2d dp = person.p_m - robot.p_m;
  const Eigen::Vector2d dv = person.v_m_s - robot.v_m_s;
  const double vv = dv.squaredNorm();
  const double t_star = vv > 0.0 ? std::clamp(-dp.dot(dv) / vv, 0.0, o.conflict_horizon_s) : 0.0;
  const double d_star = std::max(0.0, (dp + dv * t_star).norm() - robot.radius_m - person.radius_m);
  return std::exp(-d_star * d_star / (2.0 * o.conflict_sigma_m * o.conflict_sigma_m)) *
         std::exp(-t_star / o.conflict_tau_s);
}

ConflictShares conflictShares(const std::vector<AgentSample>& robot,
                              const std::vector<AgentSample>& person, const MetricsOptions& o) {
  ConflictShares s;
  const std::size_t n = std::min(robot.size(), person.size());
  auto at = [](const AgentSample& where, const AgentSample& velocity_of) {
    AgentSample a = where;
    a.v_m_s = velocity_of.v_m_s;
    return a;
  };
  for (std::size_t k = 0; k < n; ++k)
    s.max_intensity = std::max(s.max_intensity, conflictIntensity(robot[k], person[k], o));
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const AgentSample& r0 = robot[k];
    const AgentSample& r1 = robot[k + 1];
    const AgentSample& h0 = person[k];
    const AgentSample& h1 = person[k + 1];
    // Both where they are at k+1; each with its velocity of k (kept) or of k+1 (changed).
    const double i_before = conflictIntensity(r0, h0, o);
    const double i_kept = conflictIntensity(at(r1, r0), at(h1, h0), o);
    const double i_robot = conflictIntensity(r1, at(h1, h0), o);
    const double i_person = conflictIntensity(at(r1, r0), h1, o);
    const double i_both = conflictIntensity(r1, h1, o);
    s.by_time += std::abs(i_kept - i_before);
    // Shapley values of the two velocity changes: each one's effect averaged over both orders.
    const double d_robot = 0.5 * ((i_robot - i_kept) + (i_both - i_person));
    const double d_person = 0.5 * ((i_person - i_kept) + (i_both - i_robot));
    (d_robot < 0.0 ? s.resolved_by_robot : s.escalated_by_robot) += std::abs(d_robot);
    (d_person < 0.0 ? s.resolved_by_person : s.escalated_by_person) += std::abs(d_person);
  }
  if (s.max_intensity < o.conflict_min_intensity) return s;  // no conflict to share
  constexpr double kNothing = 1e-12;
  const double resolved = s.resolved_by_robot + s.resolved_by_person;
  if (resolved > kNothing) s.robot_responsibility = s.resolved_by_robot / resolved;
  const double escalated = s.escalated_by_robot + s.escalated_by_person;
  if (escalated > kNothing) s.robot_engagement = s.escalated_by_robot / escalated;
  return s;
}

RunMetrics computeRunMetrics(const RunInput& in, const MetricsOptions& o) {
  RunMetrics m;
  const auto& frames = in.frames;
  if (frames.empty()) return m;

  // The robot's part of the run: up to the frame it reached its goal, else all of it.
  double goal_time = in.goal_time_s;
  if (std::isnan(goal_time) && in.robot_goal) {
    for (const auto& f : frames)
      if ((f.robot.p_m - *in.robot_goal).norm() <= o.goal_tolerance_m) {
        goal_time = f.t_s;
        break;
      }
  }
  std::size_t end = frames.size();
  if (std::isfinite(goal_time)) {
    end = 0;
    while (end < frames.size() && frames[end].t_s <= goal_time + 1e-9) ++end;
    end = std::max<std::size_t>(end, 1);
  }
  const double t0 = frames.front().t_s;
  m.duration_s = frames[end - 1].t_s - t0;
  if (std::isfinite(goal_time)) m.time_to_goal_s = goal_time - t0;

  std::vector<Frame> run(frames.begin(), frames.begin() + static_cast<std::ptrdiff_t>(end));
  const std::vector<double> dt = holdTimes(run);
  std::vector<double> t;
  std::vector<Eigen::Vector2d> p;
  std::vector<Eigen::Vector2d> v;
  std::vector<double> theta;
  for (const auto& f : run) {
    t.push_back(f.t_s);
    p.push_back(f.robot.p_m);
    v.push_back(f.robot.v_m_s);
    theta.push_back(f.robot.theta_rad);
  }

  // Path and motion.
  m.path_length_m = pathLength(p);
  m.cumulative_heading_change_rad = cumulativeHeadingChange(theta);
  {
    double w_sum = 0.0;
    double x_sum = 0.0;
    for (std::size_t k = 0; k < run.size(); ++k) {
      const double speed = v[k].norm();
      accumulate(m.speed_m_s, speed, dt[k], w_sum, x_sum);
      m.motion_energy_m2_s += speed * speed * dt[k];
      if (speed < o.stalled_speed_m_s) m.stalled_s += dt[k];
    }
    m.speed_m_s.avg = w_sum > 0.0 ? x_sum / w_sum : (run.size() == 1 ? v[0].norm() : kNaN);
  }
  m.acceleration_m_s2 = derivativeStats(t, v, 1);
  m.jerk_m_s3 = derivativeStats(t, v, 2);

  if (in.robot_goal) {
    const Eigen::Vector2d goal = *in.robot_goal;
    const double straight = (goal - p.front()).norm();
    m.shortest_path_m = std::isfinite(in.shortest_path_m) ? in.shortest_path_m : straight;
    if (straight > 0.0) m.path_length_ratio = m.path_length_m / straight;
    m.final_distance_to_goal_m = (goal - p.back()).norm();
    if (straight > 0.0) m.goal_traversal_ratio = m.final_distance_to_goal_m / straight;
    m.path_irregularity_rad = pathIrregularity(p, theta.front(), goal, o.min_motion_m);
    if (m.path_length_m > 0.0)
      m.path_irregularity_rad_per_m = m.path_irregularity_rad / m.path_length_m;
    std::vector<double> d(p.size());
    for (std::size_t k = 0; k < p.size(); ++k) d[k] = (goal - p[k]).norm();
    m.longest_no_progress_s = longestNoProgress(t, d, o.progress_m);
  }

  // Obstacles.
  if (in.wall_clearance_m.size() == frames.size()) {
    double w_sum = 0.0;
    double x_sum = 0.0;
    bool touching = false;
    for (std::size_t k = 0; k < run.size(); ++k) {
      const double c = in.wall_clearance_m[k];
      if (!std::isfinite(c)) continue;  // off the map: unknown, not a collision nor a force
      accumulate(m.clearing_distance_m, c, dt[k], w_sum, x_sum);
      const bool now = c <= o.contact_m;
      if (now && !touching) ++m.wall_collisions;
      touching = now;
      m.obstacle_work += o.sfm_wall_a_m_s2 * std::exp(-std::max(c, 0.0) / o.sfm_wall_b_m) * dt[k];
    }
    m.clearing_distance_m.avg =
        w_sum > 0.0 ? x_sum / w_sum : (run.size() == 1 ? in.wall_clearance_m[0] : kNaN);
  }

  // People: per frame the nearest one, and per person its own series.
  std::map<std::int32_t, PersonMetrics> persons;
  std::map<std::int32_t, std::vector<AgentSample>> robot_with;  // robot samples aligned per person
  std::map<std::int32_t, std::vector<AgentSample>> person_track;
  std::map<std::int32_t, bool> touching;
  double frames_with_people = 0.0;
  double compliance_violation_s = 0.0;
  double discomfort_frames = 0.0;
  double w_sum = 0.0;
  double x_sum = 0.0;
  for (std::size_t k = 0; k < run.size(); ++k) {
    const Frame& f = run[k];
    if (f.humans.empty()) continue;
    double nearest = std::numeric_limits<double>::infinity();
    Eigen::Vector2d force_on_robot{0.0, 0.0};
    for (const auto& h : f.humans) {
      PersonMetrics& pm = persons[h.id];
      pm.id = h.id;
      const double gap = surfaceGap(f.robot, h);
      nearest = std::min(nearest, gap);
      pm.min_distance_m = std::isnan(pm.min_distance_m) ? gap : std::min(pm.min_distance_m, gap);
      const double ttc = timeToCollision(f.robot, h, o.ttc_horizon_s);
      if (std::isfinite(ttc))
        pm.min_ttc_s = std::isnan(pm.min_ttc_s) ? ttc : std::min(pm.min_ttc_s, ttc);
      const int zone = zoneOf(gap, o);
      if (zone == 0) pm.intimate_s += dt[k];
      if (zone == 1) pm.personal_s += dt[k];
      if (zone == 2) pm.social_s += dt[k];
      const bool contact = gap <= o.contact_m;
      if (contact && !touching[h.id]) {
        // Who ran into whom (HuNavSim): each one closing on the other at the contact's onset;
        // both can be, or neither (a graze at rest).
        ++pm.collisions;
        if (closingSpeed(f.robot, h) > o.ran_into_speed_m_s) ++pm.robot_on_person_collisions;
        if (closingSpeed(h, f.robot) > o.ran_into_speed_m_s) ++pm.person_on_robot_collisions;
      }
      touching[h.id] = contact;
      // Social force (Helbing & Molnár): magnitude A exp(-gap/B), along the line between them.
      const Eigen::Vector2d away = f.robot.p_m - h.p_m;
      const double force = o.sfm_a_m_s2 * std::exp(-std::max(gap, 0.0) / o.sfm_b_m);
      if (away.norm() > 0.0) force_on_robot += force * away.normalized();
      m.social_work += force * dt[k];  // the robot's on this person
      m.personal_space_cost_s += personalSpaceCost(f.robot, h, o) * dt[k];
      robot_with[h.id].push_back(f.robot);
      person_track[h.id].push_back(h);
    }
    m.social_work += force_on_robot.norm() * dt[k];
    frames_with_people += 1.0;
    accumulate(m.closest_person_distance_m, nearest, dt[k], w_sum, x_sum);
    if (nearest < o.space_compliance_m) compliance_violation_s += dt[k];
    if (nearest < o.discomfort_m) discomfort_frames += 1.0;
    const int zone = zoneOf(nearest, o);
    if (zone == 0) m.intimate_s += dt[k];
    if (zone == 1) m.personal_s += dt[k];
    if (zone == 2) m.social_s += dt[k];
  }
  if (frames_with_people > 0.0) {
    m.min_distance_to_person_m = m.closest_person_distance_m.min;
    m.closest_person_distance_m.avg = w_sum > 0.0 ? x_sum / w_sum : m.closest_person_distance_m.min;
    m.discomfort_frequency = discomfort_frames / frames_with_people;
  }
  if (m.duration_s > 0.0) {
    m.space_compliance = compliance_violation_s / m.duration_s;
    m.intimate_share = m.intimate_s / m.duration_s;
    m.personal_share = m.personal_s / m.duration_s;
    m.social_share = m.social_s / m.duration_s;
  }
  for (auto& [id, pm] : persons) {
    pm.conflict = conflictShares(robot_with[id], person_track[id], o);
    m.person_collisions += pm.collisions;
    m.robot_on_person_collisions += pm.robot_on_person_collisions;
    m.person_on_robot_collisions += pm.person_on_robot_collisions;
    if (std::isfinite(pm.min_ttc_s))
      m.min_ttc_s = std::isnan(m.min_ttc_s) ? pm.min_ttc_s : std::min(m.min_ttc_s, pm.min_ttc_s);
    m.persons.push_back(pm);
  }

  m.social_work += m.obstacle_work;

  // Outcome.
  m.collision =
      m.person_collisions > 0 || m.wall_collisions > 0 || in.outcome == Outcome::kCollision;
  const bool reached = in.outcome == Outcome::kGoalReached ||
                       (in.outcome == Outcome::kUnknown && std::isfinite(goal_time));
  m.success = reached && !m.collision;
  m.timeout = in.outcome == Outcome::kTimeLimit;
  m.failure_to_progress = !m.success && (in.outcome == Outcome::kStandstill ||
                                         (std::isfinite(m.longest_no_progress_s) &&
                                          m.longest_no_progress_s >= o.failure_to_progress_s));
  if (std::isfinite(m.shortest_path_m) && m.success)
    m.spl = m.shortest_path_m / std::max(m.path_length_m, m.shortest_path_m);
  return m;
}

}  // namespace coopnav::metrics
