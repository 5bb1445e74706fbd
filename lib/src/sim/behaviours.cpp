#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "coopnav/geometry/geometry.hpp"
#include "coopnav/sim/behaviour.hpp"
#include "coopnav/sim/body_check.hpp"

namespace coopnav::sim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Below this relative speed two agents are treated as not moving relative to each other.
constexpr double kMinRelativeSpeed_m_s = 1e-3;
/// Ray range for wall-clearance look-ups; beyond it a side is treated as free.
constexpr double kWallProbeRange_m = 6.0;
/// Time over which a human slows down when arriving at its goal (arrival behaviour).
constexpr double kArrivalTime_s = 1.0;

Eigen::Vector2d leftNormal(const Eigen::Vector2d& t) { return {-t.y(), t.x()}; }

Velocity2 toVelocity(const Eigen::Vector2d& v) { return {v.x(), v.y(), 0.0}; }

/// Preferred-speed velocity towards a carrot on the reference path, shifted laterally by
/// offset_m. Near the goal the carrot is the goal itself and the speed falls off linearly.
Velocity2 followPath(const BehaviourContext& ctx, double offset_m, double lookahead_m) {
  const Eigen::Vector2d p = ctx.self->pose.position();
  const Eigen::Vector2d goal = ctx.goal.position();
  const double to_goal_m = (goal - p).norm();
  if (to_goal_m < ctx.goal_tolerance_m || ctx.reference_path == nullptr) return {};
  const Path2& path = *ctx.reference_path;
  const auto proj = projectOntoPath(path, p);
  const double total_m = pathLength(path);
  Eigen::Vector2d carrot = goal;
  if (proj && total_m - proj->arc_length_m > lookahead_m) {
    const PathPoint pp = pointAtArc(path, proj->arc_length_m + lookahead_m);
    carrot = pp.point + offset_m * leftNormal(pp.tangent);
  }
  const Eigen::Vector2d d = carrot - p;
  if (d.norm() < 1e-9) return {};
  const double speed_m_s = std::min(ctx.preferred_speed_m_s, to_goal_m / kArrivalTime_s);
  return toVelocity(d.normalized() * speed_m_s);
}

/// Current signed offset of the human from its reference path (left > 0).
double currentOffset(const BehaviourContext& ctx) {
  const auto proj = projectOntoPath(*ctx.reference_path, ctx.self->pose.position());
  return proj ? proj->signed_distance_m : 0.0;
}

/// Largest lateral offset to `side` (+1 left, -1 right) that keeps wall_margin_m between the
/// human's body and the nearest wall, checked along the path from the human to just past the
/// crossing (so that a pillar at the crossing counts).
double wallLimitedOffset(const BehaviourContext& ctx, double side, double from_arc_m,
                         double to_arc_m, double wall_margin_m) {
  if (ctx.map == nullptr) return kInf;
  const Path2& path = *ctx.reference_path;
  double limit_m = kInf;
  constexpr double kSampleStep_m = 0.5;
  constexpr int kMaxSamples = 24;
  const double span_m = std::max(0.0, to_arc_m - from_arc_m);
  const int n = std::min(kMaxSamples, 1 + static_cast<int>(std::ceil(span_m / kSampleStep_m)));
  for (int i = 0; i <= n; ++i) {
    const double s = from_arc_m + span_m * static_cast<double>(i) / static_cast<double>(n);
    const PathPoint pp = pointAtArc(path, s);
    const Eigen::Vector2d dir = side * leftNormal(pp.tangent);
    const DistanceResult r = ctx.map->ray(pp.point, dir, kWallProbeRange_m);
    double free_m = kInf;
    if (r.status == DistanceStatus::kOk) free_m = r.distance_m;
    if (r.status == DistanceStatus::kInObstacle) free_m = 0.0;
    limit_m = std::min(limit_m, free_m - ctx.self->radius_m - wall_margin_m);
  }
  return std::max(0.0, limit_m);
}

/// Side (+1 left / -1 right of the path) away from the robot's predicted lateral position; a
/// dead-on robot gets the human's right (the human–human keep-right bias, Moussaïd et al. 2009).
double sideAwayFrom(double robot_lateral_m) { return robot_lateral_m < -1e-3 ? 1.0 : -1.0; }

/// The TEB-like last-moment sidestep of the minimally contributing human. Latches its side and
/// the largest sidestep of an encounter so that the human does not oscillate while passing.
class MinimalAvoidance {
 public:
  explicit MinimalAvoidance(const MinimalParams& p) : p_(p) {}

  /// Commanded offset for this step (0 = on the path); sets active().
  double update(const BehaviourContext& ctx, const std::optional<Encounter>& enc) {
    if (!enc) return reset();
    if (active_ && enc->along_m < -(ctx.robot->radius_m + ctx.self->radius_m)) return reset();
    const bool threat = enc->closing && enc->along_m > 0.0 &&
                        (enc->t_closest_s < p_.horizon_s || enc->gap_m < p_.trigger_gap_m);
    if (threat) {
      const double required_m = ctx.robot->radius_m + ctx.self->radius_m + p_.clearance_margin_m;
      const double needed_m = required_m - std::abs(enc->robot_lateral_m);
      if (needed_m > 0.0) {
        if (!active_) side_ = sideAwayFrom(enc->robot_lateral_m);
        const double from_arc = projectOntoPath(*ctx.reference_path, ctx.self->pose.position())
                                    .value_or(PathProjection{})
                                    .arc_length_m;
        const double wall_m =
            wallLimitedOffset(ctx, side_, from_arc, enc->crossing_arc_m, p_.wall_margin_m);
        magnitude_m_ = std::max(magnitude_m_, std::min({needed_m, p_.max_deviation_m, wall_m}));
        active_ = true;
      }
    }
    return active_ ? side_ * magnitude_m_ : 0.0;
  }
  bool active() const { return active_; }

 private:
  double reset() {
    active_ = false;
    magnitude_m_ = 0.0;
    return 0.0;
  }
  MinimalParams p_;
  bool active_{false};
  double side_{-1.0};
  double magnitude_m_{0.0};
};

/// The lateral yield of the facilitating behaviours (see YieldParams).
class Yield {
 public:
  explicit Yield(const YieldParams& p) : p_(p) {}

  /// Starts yielding to `side` by `magnitude_m` (clamped by walls).
  void engage(const BehaviourContext& ctx, const Encounter& enc, double side, double magnitude_m) {
    side_ = side;
    const double from_arc = projectOntoPath(*ctx.reference_path, ctx.self->pose.position())
                                .value_or(PathProjection{})
                                .arc_length_m;
    const double to_arc = std::max(from_arc, enc.crossing_arc_m) + 1.0;
    const double wall_m = wallLimitedOffset(ctx, side, from_arc, to_arc, p_.wall_margin_m);
    magnitude_m_ = std::min(magnitude_m, wall_m);
    active_ = true;
  }
  /// True once the robot is behind: the yield ends and the human returns to its path.
  bool released(const BehaviourContext& ctx, const std::optional<Encounter>& enc) const {
    return !enc || enc->along_m < -(p_.release_behind_m + ctx.robot->radius_m);
  }
  void release() { active_ = false; }
  bool active() const { return active_; }
  double offset() const { return active_ ? side_ * magnitude_m_ : 0.0; }
  double side() const { return side_; }
  const YieldParams& params() const { return p_; }

 private:
  YieldParams p_;
  bool active_{false};
  double side_{-1.0};
  double magnitude_m_{0.0};
};

/// Is the robot coming towards this human, close enough in lateral terms to matter?
bool engaging(const Encounter& enc, const YieldParams& y) {
  return enc.closing && enc.along_m > 0.0 && std::abs(enc.robot_lateral_m) < y.engage_lateral_m;
}

// ---------------------------------------------------------------------------------------------

class ObliviousBehaviour final : public HumanBehaviour {
 public:
  explicit ObliviousBehaviour(const ObliviousParams& p) : p_(p) {}
  Velocity2 desiredVelocity(const BehaviourContext& ctx) override {
    return followPath(ctx, 0.0, p_.lookahead_m);
  }
  BehaviourStatus status() const override { return {"follow", 0.0}; }
  const char* name() const override { return "oblivious"; }

 private:
  ObliviousParams p_;
};

class MinimalBehaviour final : public HumanBehaviour {
 public:
  explicit MinimalBehaviour(const MinimalParams& p) : p_(p), avoid_(p) {}
  Velocity2 desiredVelocity(const BehaviourContext& ctx) override {
    offset_m_ = avoid_.update(ctx, estimateEncounter(ctx));
    return followPath(ctx, offset_m_, p_.lookahead_m);
  }
  BehaviourStatus status() const override {
    return {avoid_.active() ? "avoid" : "follow", offset_m_};
  }
  const char* name() const override { return "minimal"; }

 private:
  MinimalParams p_;
  MinimalAvoidance avoid_;
  double offset_m_{0.0};
};

/// Facilitating (analytic mode): an early lateral yield away from the robot, triggered by time to
/// closest approach or distance: an explicit earlier lane shift, because plain social-force
/// humans barely cooperate head-on (with lightsfm's defaults a 0.16–0.24 m shift starting only
/// 0.3–0.45 s before the crossing).
class FacilitatingBehaviour final : public HumanBehaviour {
 public:
  FacilitatingBehaviour(const FacilitatingParams& p, std::unique_ptr<HumanPlannerAdapter> planner,
                        std::optional<double> onset_s)
      : p_(p), yield_(p.yield), planner_(std::move(planner)), onset_s_(onset_s) {}
  Velocity2 desiredVelocity(const BehaviourContext& ctx) override {
    if (planner_) {
      if (auto v = planner_->plan(ctx)) {
        mode_ = "plan";
        return *v;
      }
    }
    const auto enc = estimateEncounter(ctx);
    if (yield_.active() && yield_.released(ctx, enc)) yield_.release();
    const bool triggered = enc && (onset_s_ ? enc->t_closest_s < *onset_s_
                                            : enc->t_closest_s < p_.trigger_ttc_s ||
                                                  enc->distance_m < p_.trigger_distance_m);
    if (!yield_.active() && enc && engaging(*enc, p_.yield) && triggered) {
      yield_.engage(ctx, *enc, sideAwayFrom(enc->robot_lateral_m), p_.yield.offset_m);
    }
    mode_ = yield_.active() ? "yield" : "follow";
    return followPath(ctx, yield_.offset(), p_.yield.lookahead_m);
  }
  BehaviourStatus status() const override { return {mode_, yield_.offset()}; }
  const char* name() const override { return "facilitating"; }

 private:
  FacilitatingParams p_;
  Yield yield_;
  std::unique_ptr<HumanPlannerAdapter> planner_;
  std::optional<double> onset_s_;  ///< realistic timing: replaces both triggers
  std::string mode_{"follow"};
};

class LateFacilitatingBehaviour final : public HumanBehaviour {
 public:
  LateFacilitatingBehaviour(const LateFacilitatingParams& p, std::optional<double> onset_s)
      : p_(p), avoid_(p.minimal), yield_(p.yield), onset_s_(onset_s) {}
  Velocity2 desiredVelocity(const BehaviourContext& ctx) override {
    const auto enc = estimateEncounter(ctx);
    if (yield_.active() && yield_.released(ctx, enc)) yield_.release();
    if (!yield_.active() && enc && engaging(*enc, p_.yield) &&
        enc->t_closest_s < onset_s_.value_or(p_.trigger_ttc_s))
      yield_.engage(ctx, *enc, sideAwayFrom(enc->robot_lateral_m), p_.yield.offset_m);
    const double minimal_m = avoid_.update(ctx, enc);
    // Yielding supersedes the sidestep, but never by less than the sidestep already taken.
    offset_m_ = yield_.active() && std::abs(yield_.offset()) >= std::abs(minimal_m)
                    ? yield_.offset()
                    : minimal_m;
    const double lookahead_m = yield_.active() ? p_.yield.lookahead_m : p_.minimal.lookahead_m;
    return followPath(ctx, offset_m_, lookahead_m);
  }
  BehaviourStatus status() const override {
    return {yield_.active() ? "yield" : (avoid_.active() ? "avoid" : "follow"), offset_m_};
  }
  const char* name() const override { return "late_facilitating"; }

 private:
  LateFacilitatingParams p_;
  MinimalAvoidance avoid_;
  Yield yield_;
  std::optional<double> onset_s_;  ///< realistic timing: replaces trigger_ttc_s
  double offset_m_{0.0};
};

/// Responsive (ResponsiveParams): minimal until the robot's words reach it, then it acts on them
/// as a person told so would. The simulator has already decided whether it heard and complies,
/// and when it starts acting (ctx.cues).
class ResponsiveBehaviour final : public HumanBehaviour {
 public:
  ResponsiveBehaviour(const ResponsiveParams& p, std::optional<double> onset_s)
      : p_(p), avoid_(p.minimal), yield_(p.yield), onset_s_(onset_s) {}
  Velocity2 desiredVelocity(const BehaviourContext& ctx) override {
    const auto enc = estimateEncounter(ctx);
    if (yield_.active() && yield_.released(ctx, enc)) {
      // The robot is behind: the encounter is over, and so is what was said for it.
      yield_.release();
      going_on_ = false;
      told_side_.reset();
    }
    if (ctx.cues != nullptr) {
      for (const Cue& c : *ctx.cues) {
        // Realistic timing: told which side the robot takes, a person keeps to the other one
        // when walkers start to step aside (its onset), not as soon as it heard.
        if (onset_s_ && c.kind == CueKind::kKeepSide) {
          told_side_ = c;
          continue;
        }
        if (c.kind == CueKind::kRobotMakesRoom) told_side_.reset();
        act(c, ctx, enc);
      }
    }
    if (told_side_ && enc && enc->t_closest_s < *onset_s_) {
      act(*told_side_, ctx, enc);
      told_side_.reset();
    }
    const double minimal_m = avoid_.update(ctx, enc);
    // The shift it was told to make supersedes the sidestep, never by less than the sidestep.
    offset_m_ = yield_.active() && std::abs(yield_.offset()) >= std::abs(minimal_m)
                    ? yield_.offset()
                    : minimal_m;
    const double lookahead_m = yield_.active() ? p_.yield.lookahead_m : p_.minimal.lookahead_m;
    return followPath(ctx, offset_m_, lookahead_m);
  }
  BehaviourStatus status() const override {
    if (going_on_) return {"go_on", offset_m_};
    return {yield_.active() ? "yield" : (avoid_.active() ? "avoid" : "follow"), offset_m_};
  }
  const char* name() const override { return "responsive"; }

 private:
  void act(const Cue& c, const BehaviourContext& ctx, const std::optional<Encounter>& enc) {
    switch (c.kind) {
      case CueKind::kThank:
        return;
      case CueKind::kRobotMakesRoom:
        // The robot will wait: walk on past it (the body check squeezes past a robot at rest).
        going_on_ = true;
        yield_.release();
        return;
      case CueKind::kKeepSide:
      case CueKind::kMoveToSide:
        break;
    }
    if (going_on_ || !enc || !(enc->along_m > 0.0)) return;  // nothing ahead to make room for
    const double side = c.side == Side::kLeft    ? 1.0
                        : c.side == Side::kRight ? -1.0
                                                 : sideAwayFrom(enc->robot_lateral_m);
    double magnitude_m = c.kind == CueKind::kMoveToSide ? p_.yield.offset_m : p_.inform_offset_m;
    // Told again, a person does more, and never steps back towards the robot.
    if (yield_.active() && yield_.side() == side)
      magnitude_m = std::max(magnitude_m, std::abs(yield_.offset()));
    if (c.repeat) magnitude_m += p_.repeat_increment_m;
    yield_.engage(ctx, *enc, side, magnitude_m);
  }

  ResponsiveParams p_;
  MinimalAvoidance avoid_;
  Yield yield_;
  std::optional<double> onset_s_;  ///< realistic timing (AvoidanceTiming::kRealistic)
  std::optional<Cue> told_side_;   ///< a statement heard, kept until the onset
  bool going_on_{false};
  double offset_m_{0.0};
};

/// Social force model (see SocialForceParams for the references).
class SocialForceBehaviour final : public HumanBehaviour {
 public:
  explicit SocialForceBehaviour(const SocialForceParams& p) : p_(p) {}

  Velocity2 desiredVelocity(const BehaviourContext& ctx) override {
    const Eigen::Vector2d p = ctx.self->pose.position();
    const Eigen::Vector2d v{ctx.self->velocity.vx_m_s, ctx.self->velocity.vy_m_s};
    // Driving term (Helbing & Molnár 1995): relax towards the preferred velocity along the path.
    const Velocity2 want = followPath(ctx, 0.0, p_.lookahead_m);
    const Eigen::Vector2d v0{want.vx_m_s, want.vy_m_s};
    if (v0.squaredNorm() == 0.0 && (ctx.goal.position() - p).norm() < ctx.goal_tolerance_m)
      return {};
    Eigen::Vector2d force = p_.goal_weight * (v0 - v) / p_.relaxation_time_s;
    // Agent interactions (Moussaïd et al. 2009).
    if (ctx.robot != nullptr) force += p_.robot_weight * interaction(*ctx.self, *ctx.robot);
    if (ctx.other_humans != nullptr)
      for (const AgentState& o : *ctx.other_humans)
        force += p_.social_weight * interaction(*ctx.self, o);
    // Walls: exponential repulsion from the nearest obstacle surface.
    if (ctx.map != nullptr) {
      const DistanceResult r = ctx.map->nearest(p);
      if (r.status == DistanceStatus::kOk && r.distance_m > 1e-6) {
        const Eigen::Vector2d away = (p - r.obstacle) / r.distance_m;
        const double surface_m = r.distance_m - ctx.self->radius_m;
        force += p_.obstacle_weight * std::exp(-surface_m / p_.obstacle_sigma_m) * away;
      }
    }
    Eigen::Vector2d v_next = v + force * ctx.dt_s;
    const double cap_m_s = p_.max_speed_factor * ctx.preferred_speed_m_s;
    if (v_next.norm() > cap_m_s) v_next *= cap_m_s / v_next.norm();
    offset_m_ = currentOffset(ctx);
    return toVelocity(v_next);
  }
  BehaviourStatus status() const override { return {"social_force", offset_m_}; }
  const char* name() const override { return "social_force"; }

 private:
  /// Moussaïd et al. 2009, eqs. for f_v (deceleration) and f_theta (turning): interaction vector
  /// I = lambda (v_a - v_b) + e_ab, B = gamma |I|, theta = angle from I to e_ab.
  Eigen::Vector2d interaction(const AgentState& a, const AgentState& b) const {
    const Eigen::Vector2d diff = b.pose.position() - a.pose.position();
    const double centre_m = diff.norm();
    if (centre_m < 1e-9 || centre_m > p_.neighbour_range_m) return {0.0, 0.0};
    const double d_m = std::max(0.0, centre_m - (a.radius_m + b.radius_m) + p_.body_reference_m);
    const Eigen::Vector2d e_ab = diff / centre_m;
    const Eigen::Vector2d va{a.velocity.vx_m_s, a.velocity.vy_m_s};
    const Eigen::Vector2d vb{b.velocity.vx_m_s, b.velocity.vy_m_s};
    const Eigen::Vector2d interaction_vec = p_.lambda * (va - vb) + e_ab;
    const double i_norm = interaction_vec.norm();
    if (i_norm < 1e-9) return {0.0, 0.0};
    const Eigen::Vector2d t = interaction_vec / i_norm;
    const Eigen::Vector2d n_left = leftNormal(t);
    const double theta = std::atan2(cross2(t, e_ab), t.dot(e_ab));
    // A tiny bias breaks the dead-on symmetry towards passing on the right, as real pedestrians
    // do (Moussaïd et al. 2009 use the same device).
    constexpr double kThetaBias_rad = 0.005;
    const double theta_b = theta + kThetaBias_rad;
    const double b_m = p_.gamma * i_norm;
    const double f_v = -std::exp(-d_m / b_m - std::pow(p_.n_prime * b_m * theta_b, 2));
    const double f_theta =
        -(theta_b > 0.0 ? 1.0 : -1.0) * std::exp(-d_m / b_m - std::pow(p_.n * b_m * theta_b, 2));
    return f_v * t + f_theta * n_left;
  }

  SocialForceParams p_;
  double offset_m_{0.0};
};

/// Every model but oblivious: its velocity, then the body check (body_check.hpp). One wrapper, so
/// that each model keeps only its own avoidance logic.
class BodyCheckedBehaviour final : public HumanBehaviour {
 public:
  BodyCheckedBehaviour(std::unique_ptr<HumanBehaviour> model, const BodyCheckParams& p)
      : model_(std::move(model)), check_(p) {}
  Velocity2 desiredVelocity(const BehaviourContext& ctx) override {
    const Velocity2 want = model_->desiredVelocity(ctx);
    return check_.apply(ctx, want, model_->status().target_offset_m);
  }
  BehaviourStatus status() const override {
    BehaviourStatus s = model_->status();
    if (check_.mode() == BodyCheckMode::kSqueeze) {
      s.mode = "squeeze";
      s.target_offset_m = check_.targetOffset();
    } else if (check_.mode() == BodyCheckMode::kWait) {
      s.mode = "wait";
    }
    return s;
  }
  const char* name() const override { return model_->name(); }

 private:
  std::unique_ptr<HumanBehaviour> model_;
  BodyCheck check_;
};

/// A person who stops for a while (PauseParams): the model runs every step as usual, so that
/// what it remembers (a side chosen, a yield under way) stays its own, but while the pause lasts
/// the person stands. Standing is what a person reading a phone does whoever comes: no body check
/// is needed to stand still.
class PausingBehaviour final : public HumanBehaviour {
 public:
  PausingBehaviour(std::unique_ptr<HumanBehaviour> model, const PauseParams& p)
      : model_(std::move(model)), p_(p) {}
  Velocity2 desiredVelocity(const BehaviourContext& ctx) override {
    const Velocity2 want = model_->desiredVelocity(ctx);
    if (!since_s_ && ctx.self != nullptr && ctx.reference_path != nullptr &&
        ctx.reference_path->size() >= 2) {
      const auto proj = projectOntoPath(*ctx.reference_path, ctx.self->pose.position());
      if (proj && proj->arc_length_m >= p_.after_m) since_s_ = ctx.t_s;
    }
    paused_ = since_s_ && ctx.t_s - *since_s_ < p_.duration_s - 1e-9;
    return paused_ ? Velocity2{} : want;
  }
  BehaviourStatus status() const override {
    BehaviourStatus s = model_->status();
    if (paused_) s.mode = "pause";
    return s;
  }
  const char* name() const override { return model_->name(); }

 private:
  std::unique_ptr<HumanBehaviour> model_;
  PauseParams p_;
  std::optional<double> since_s_;  ///< [s] sim time the pause began
  bool paused_{false};
};

std::unique_ptr<HumanBehaviour> makeModel(const BehaviourConfig& config,
                                          const PlannerAdapterFactory& planner_factory) {
  switch (config.type) {
    case BehaviourType::kMinimal:
      return std::make_unique<MinimalBehaviour>(config.minimal);
    case BehaviourType::kOblivious:
      return std::make_unique<ObliviousBehaviour>(config.oblivious);
    case BehaviourType::kSocialForce:
      return std::make_unique<SocialForceBehaviour>(config.social_force);
    case BehaviourType::kLateFacilitating:
      return std::make_unique<LateFacilitatingBehaviour>(config.late_facilitating, config.onset_s);
    case BehaviourType::kResponsive:
      return std::make_unique<ResponsiveBehaviour>(config.responsive, config.onset_s);
    case BehaviourType::kFacilitating: {
      std::unique_ptr<HumanPlannerAdapter> planner;
      if (config.facilitating.planner == "band") {
        if (!planner_factory)
          throw std::invalid_argument(
              "behaviour facilitating with planner: band needs the dual-band planner adapter, "
              "which this build does not provide; use planner: analytic");
        planner = planner_factory(config.facilitating);
      }
      return std::make_unique<FacilitatingBehaviour>(config.facilitating, std::move(planner),
                                                     config.onset_s);
    }
    case BehaviourType::kRecorded:
      return makeRecordedBehaviour(config.recorded);
  }
  throw std::invalid_argument("unknown behaviour type");
}

}  // namespace

// ---------------------------------------------------------------------------------------------

double pathLength(const Path2& path) {
  double len = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) len += (path[i] - path[i - 1]).norm();
  return len;
}

PathPoint pointAtArc(const Path2& path, double s_m) {
  PathPoint out;
  if (path.empty()) return out;
  out.point = path.front();
  double acc = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector2d seg = path[i] - path[i - 1];
    const double len = seg.norm();
    if (len <= 0.0) continue;
    out.tangent = seg / len;
    if (acc + len >= s_m || i + 1 == path.size()) {
      const double f = std::clamp((s_m - acc) / len, 0.0, 1.0);
      out.point = path[i - 1] + f * seg;
      return out;
    }
    acc += len;
  }
  return out;
}

std::optional<Encounter> estimateEncounter(const BehaviourContext& ctx) {
  if (ctx.robot == nullptr || ctx.self == nullptr || ctx.reference_path == nullptr ||
      ctx.reference_path->size() < 2)
    return std::nullopt;
  const Eigen::Vector2d ph = ctx.self->pose.position();
  const Eigen::Vector2d pr = ctx.robot->pose.position();
  const Eigen::Vector2d vh{ctx.self->velocity.vx_m_s, ctx.self->velocity.vy_m_s};
  const Eigen::Vector2d vr{ctx.robot->velocity.vx_m_s, ctx.robot->velocity.vy_m_s};
  const auto proj = projectOntoPath(*ctx.reference_path, ph);
  if (!proj) return std::nullopt;
  const PathPoint here = pointAtArc(*ctx.reference_path, proj->arc_length_m);

  Encounter e;
  const Eigen::Vector2d dp = pr - ph;
  const Eigen::Vector2d dv = vr - vh;
  e.distance_m = dp.norm();
  e.gap_m = e.distance_m - ctx.robot->radius_m - ctx.self->radius_m;
  e.along_m = dp.dot(here.tangent);
  e.closing = dp.dot(dv) < 0.0;
  const double dv2 = dv.squaredNorm();
  e.t_closest_s = (e.closing && dv2 > kMinRelativeSpeed_m_s * kMinRelativeSpeed_m_s)
                      ? -dp.dot(dv) / dv2
                      : (e.closing ? kInf : 0.0);
  const double t = std::isfinite(e.t_closest_s) ? e.t_closest_s : 0.0;
  // Prefer the robot's published band for where it will be; else constant velocity.
  Eigen::Vector2d pr_future = pr + vr * t;
  if (ctx.robot_band != nullptr && !ctx.robot_band->poses.empty()) {
    const double tb = ctx.t_s + t - ctx.robot_band_stamp_s;
    const auto& poses = ctx.robot_band->poses;
    if (tb >= poses.front().t_s && tb <= poses.back().t_s) {
      for (std::size_t i = 1; i < poses.size(); ++i) {
        if (poses[i].t_s >= tb) {
          const double span = poses[i].t_s - poses[i - 1].t_s;
          const double f = span > 0.0 ? (tb - poses[i - 1].t_s) / span : 1.0;
          pr_future = (1.0 - f) * poses[i - 1].pose.position() + f * poses[i].pose.position();
          break;
        }
      }
    }
  }
  const double along_speed_m_s = std::max(0.0, vh.dot(here.tangent));
  e.crossing_arc_m = proj->arc_length_m + along_speed_m_s * t;
  const PathPoint cross_pt = pointAtArc(*ctx.reference_path, e.crossing_arc_m);
  e.robot_lateral_m = cross2(cross_pt.tangent, pr_future - cross_pt.point);
  return e;
}

const char* toString(CueKind k) {
  switch (k) {
    case CueKind::kKeepSide:
      return "keep_side";
    case CueKind::kMoveToSide:
      return "move_to_side";
    case CueKind::kRobotMakesRoom:
      return "robot_makes_room";
    case CueKind::kThank:
      return "thank";
  }
  return "?";
}

const char* toString(BehaviourType t) {
  switch (t) {
    case BehaviourType::kMinimal:
      return "minimal";
    case BehaviourType::kOblivious:
      return "oblivious";
    case BehaviourType::kSocialForce:
      return "social_force";
    case BehaviourType::kLateFacilitating:
      return "late_facilitating";
    case BehaviourType::kResponsive:
      return "responsive";
    case BehaviourType::kFacilitating:
      return "facilitating";
    case BehaviourType::kRecorded:
      return "recorded";
  }
  return "?";
}

const char* toString(AvoidanceTiming t) {
  switch (t) {
    case AvoidanceTiming::kTrigger:
      return "trigger";
    case AvoidanceTiming::kRealistic:
      return "realistic";
  }
  return "?";
}

bool parseAvoidanceTiming(const std::string& s, AvoidanceTiming& out) {
  for (const AvoidanceTiming t : {AvoidanceTiming::kTrigger, AvoidanceTiming::kRealistic})
    if (s == toString(t)) {
      out = t;
      return true;
    }
  return false;
}

std::vector<std::string> behaviourTypeNames() {
  return {"minimal",    "oblivious",    "social_force", "late_facilitating",
          "responsive", "facilitating", "recorded"};
}

bool parseBehaviourType(const std::string& s, BehaviourType& out) {
  for (auto t : {BehaviourType::kMinimal, BehaviourType::kOblivious, BehaviourType::kSocialForce,
                 BehaviourType::kLateFacilitating, BehaviourType::kResponsive,
                 BehaviourType::kFacilitating, BehaviourType::kRecorded}) {
    if (s == toString(t)) {
      out = t;
      return true;
    }
  }
  return false;
}

std::unique_ptr<HumanBehaviour> makeBehaviour(const BehaviourConfig& config,
                                              const PlannerAdapterFactory& planner_factory) {
  std::unique_ptr<HumanBehaviour> model = makeModel(config, planner_factory);
  // Only the oblivious human walks into a robot in its way; a recorded one is a replay.
  if (config.type == BehaviourType::kRecorded) return model;
  if (config.type != BehaviourType::kOblivious)
    model = std::make_unique<BodyCheckedBehaviour>(std::move(model), config.body_check);
  if (config.pause.duration_s > 0.0)
    model = std::make_unique<PausingBehaviour>(std::move(model), config.pause);
  return model;
}

}  // namespace coopnav::sim
