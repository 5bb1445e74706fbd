#pragma once
/// @file Simulated human behaviours: the interface the world simulator calls every physics step,
/// the context it passes, and the parameters of each model. Pure: no I/O, no clock.
///
/// Every behaviour walks its reference path (start -> via points -> goal; the human's "initial
/// shortest path" of paper §II-C) and expresses avoidance as a signed lateral offset from that
/// path (> 0 = to the path's left), so that the deviation CA the assessors measure is exactly what
/// the model commands.

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coopnav/distance/distance_map.hpp"
#include "coopnav/geometry/types.hpp"
#include "coopnav/sim/recorded.hpp"

namespace coopnav::sim {

/// What an utterance of the robot means to the person it is addressed to (the dialogue manager's
/// speech acts, as a person takes them).
enum class CueKind : std::uint8_t {
  kKeepSide,        ///< "I will pass on your left" (or its repeat): keep to the other side
  kMoveToSide,      ///< "Could you move to your right?" (or "a little more"): a request
  kRobotMakesRoom,  ///< "I will wait here for you to pass" (dock, wider place, retreat, stop): go
                    ///< on
  kThank,           ///< "Thank you": nothing to do
};
const char* toString(CueKind k);

/// An utterance addressed to one human.
struct Cue {
  std::int32_t human_id{0};
  CueKind kind{CueKind::kMoveToSide};
  /// Side to keep to or move to, from the human's own view; kUndefined = the side away from the
  /// robot (e.g. "It is narrow here. I will wait at the side if needed.").
  Side side{Side::kUndefined};
  bool repeat{false};  ///< the robot says it again or asks for more: a person does more
  /// Sim time at which the words have been heard (the end of the utterance); for the cues a
  /// behaviour sees (BehaviourContext::cues), the time it starts acting on them.
  double t_s{0.0};
};

/// What became of a cue once its words were heard (Simulation; reported for the logs).
struct CueOutcome {
  Cue cue;
  double distance_m{0.0};  ///< robot-human centre distance when the words ended
  bool responds{false};    ///< the human's behaviour reacts to words at all (responsive)
  bool heard{false};       ///< within hearing_range_m
  bool complies{false};    ///< heard, and the compliance draw said yes
  double act_s{0.0};       ///< when it starts acting on it (heard + reaction time), if it complies
};

/// Everything a behaviour may look at. Pointers are non-owning and valid for the call only.
struct BehaviourContext {
  double t_s{0.0};    ///< current sim time [s]
  double dt_s{0.05};  ///< physics step [s]
  const AgentState* self{nullptr};
  Pose2 goal;
  const Path2* reference_path{nullptr};  ///< start -> via -> goal, >= 2 points
  double preferred_speed_m_s{1.0};
  double goal_tolerance_m{0.2};
  double max_acc_m_s2{1.5};          ///< the human's walking acceleration limit
  const AgentState* robot{nullptr};  ///< nullptr when the world has no robot
  const Band* robot_band{nullptr};   ///< last band the robot published, nullptr if none
  double robot_band_stamp_s{0.0};    ///< sim time of the band's t_s = 0
  const std::vector<AgentState>* other_humans{nullptr};  ///< never contains self
  const DistanceMap* map{nullptr};                       ///< nullptr = no walls
  /// Cues addressed to this human that it has heard, complies with and starts acting on in this
  /// step (t_s = when it starts acting), in that order: each is given once, the behaviour keeps
  /// what it makes of it.
  const std::vector<Cue>* cues{nullptr};
};

/// What a behaviour is doing, for logs and tests.
struct BehaviourStatus {
  std::string mode{"follow"};   ///< e.g. follow, avoid, yield, return
  double target_offset_m{0.0};  ///< commanded lateral offset from the reference path, left > 0
};

/// A human's decision model. Stateful (e.g. it remembers the side it chose), deterministic.
class HumanBehaviour {
 public:
  virtual ~HumanBehaviour() = default;
  /// Desired world-frame velocity for this physics step; the simulator then applies the human's
  /// acceleration limit (omega is ignored: a human's heading follows its velocity).
  virtual Velocity2 desiredVelocity(const BehaviourContext& ctx) = 0;
  virtual BehaviourStatus status() const = 0;
  virtual const char* name() const = 0;
};

// ---- Parameters. In-class initialisers are the only defaults; visit() lists every key once as
// v.number(key, field, min, max), v.choice(key, field, {allowed...}) so that loaders validate
// without lib/ knowing any file format.

/// "Minimally contributing" (paper §III; TEB-like): keeps to its path and treats the robot as an
/// obstacle only within a short horizon, sidestepping just enough to keep its clearance.
struct MinimalParams {
  double horizon_s{1.5};           ///< reacts when time to closest approach < this
  double trigger_gap_m{0.6};       ///< ... or when the surface gap to the robot is below this
  double clearance_margin_m{0.1};  ///< wanted surface gap beyond the two radii
  double max_deviation_m{0.3};     ///< cap of the sidestep: it never does more than this
  double lookahead_m{0.6};         ///< path-following carrot distance (short = brisk sidestep)
  double wall_margin_m{0.1};       ///< kept between its body and a wall when stepping aside
  template <class V>
  void visit(V& v) {
    v.number("horizon_s", horizon_s, 0.0, 10.0);
    v.number("trigger_gap_m", trigger_gap_m, 0.0, 5.0);
    v.number("clearance_margin_m", clearance_margin_m, 0.0, 2.0);
    v.number("max_deviation_m", max_deviation_m, 0.0, 3.0);
    v.number("lookahead_m", lookahead_m, 0.1, 5.0);
    v.number("wall_margin_m", wall_margin_m, 0.0, 2.0);
  }
};

/// Never avoids anyone: walks its path at its preferred speed.
struct ObliviousParams {
  double lookahead_m{1.0};
  template <class V>
  void visit(V& v) {
    v.number("lookahead_m", lookahead_m, 0.1, 5.0);
  }
};

/// Social force model: driving term of Helbing & Molnár 1995 (Phys. Rev. E 51:4282,
/// doi 10.1103/PhysRevE.51.4282), agent interaction of Moussaïd et al. 2009 (Proc. R. Soc. B
/// 276:2755, doi 10.1098/rspb.2009.0405), wall repulsion exp(-d/sigma). Defaults: Moussaïd's
/// interaction constants and the weights lightsfm / libpedsim use with them, except where noted.
struct SocialForceParams {
  double relaxation_time_s{0.5};  ///< tau of the driving term
  /// Driving-term weight: 1 as in Helbing & Molnár (lightsfm uses 2.0, which pulls a human back
  /// onto its line so hard that it collides with a robot passing 0.4 m off its line).
  double goal_weight{1.0};
  double social_weight{2.1};  ///< weight of the interaction with other humans
  /// Weight of the interaction with the robot: HuNavSim raises the social factor to 5.0 so that
  /// humans keep clear of robots; with 2.1 a head-on human passes a 0.47 m robot too closely
  /// (simulated head-on at 1.3 m/s against a robot at 0.3-0.7 m/s, this model shifts the human
  /// only 0.16-0.24 m, starting 0.3-0.45 s before the crossing).
  double robot_weight{5.0};
  double lambda{2.0};   ///< Moussaïd: velocity-difference weight in the interaction vector
  double gamma{0.35};   ///< Moussaïd: B = gamma * |I|
  double n{2.0};        ///< Moussaïd: angular interaction range (deceleration term)
  double n_prime{3.0};  ///< Moussaïd: angular interaction range (turning term)
  double obstacle_weight{10.0};
  double obstacle_sigma_m{0.2};
  double neighbour_range_m{10.0};  ///< agents farther than this exert no force
  double max_speed_factor{1.3};    ///< speed cap = factor * preferred speed (Helbing & Molnár)
  double body_reference_m{0.6};    ///< Moussaïd's distances are centre distances of two ~0.3 m
                                   ///< pedestrians; bigger bodies shift d by their extra size
  /// Carrot distance of the driving direction. Far, so that the desired direction is "towards the
  /// goal" as in the SFM rather than a stiff pull back onto the path.
  double lookahead_m{5.0};
  template <class V>
  void visit(V& v) {
    v.number("relaxation_time_s", relaxation_time_s, 0.05, 5.0);
    v.number("goal_weight", goal_weight, 0.0, 100.0);
    v.number("social_weight", social_weight, 0.0, 100.0);
    v.number("robot_weight", robot_weight, 0.0, 100.0);
    v.number("lambda", lambda, 0.0, 10.0);
    v.number("gamma", gamma, 0.01, 10.0);
    v.number("n", n, 0.0, 10.0);
    v.number("n_prime", n_prime, 0.0, 10.0);
    v.number("obstacle_weight", obstacle_weight, 0.0, 1000.0);
    v.number("obstacle_sigma_m", obstacle_sigma_m, 0.01, 5.0);
    v.number("neighbour_range_m", neighbour_range_m, 0.0, 100.0);
    v.number("max_speed_factor", max_speed_factor, 1.0, 3.0);
    v.number("body_reference_m", body_reference_m, 0.0, 2.0);
    v.number("lookahead_m", lookahead_m, 0.1, 5.0);
  }
};

/// Lateral yield shared by the yielding behaviours: shift by offset_m to the side away from the
/// robot (or the asked side), limited so that wall_margin_m stays between body and wall; hold it
/// until the robot is behind, then return to the path.
struct YieldParams {
  double offset_m{0.9};          ///< wanted lateral shift [m] (paper Table I: CM 0.94 m, open)
  double wall_margin_m{0.3};     ///< pedestrians keep ~0.3 m from walls (HCM shy distance)
  double lookahead_m{1.0};       ///< carrot distance while shifting: time constant ~ L / v
  double engage_lateral_m{2.0};  ///< yields only if the robot's predicted lateral offset from
                                 ///< the path at the crossing is below this
  double release_behind_m{0.3};  ///< returns once the robot is this far behind (along the path)
  template <class V>
  void visit(V& v) {
    v.number("offset_m", offset_m, 0.0, 3.0);
    v.number("wall_margin_m", wall_margin_m, 0.0, 2.0);
    v.number("lookahead_m", lookahead_m, 0.1, 5.0);
    v.number("engage_lateral_m", engage_lateral_m, 0.0, 10.0);
    v.number("release_behind_m", release_behind_m, 0.0, 10.0);
  }
};

/// "Facilitating" (paper §III): yields early, as a second CoHAN instance planning for the human
/// would. planner: analytic = the early-yield model below; band = a HumanPlannerAdapter (the
/// dual-band planner with the robot as the anticipated other agent) supplied by the caller.
struct FacilitatingParams {
  std::string planner{"analytic"};
  double trigger_ttc_s{5.0};       ///< starts yielding when time to closest approach < this
  double trigger_distance_m{7.0};  ///< ... or the robot is approaching and closer than this
  YieldParams yield;
  template <class V>
  void visit(V& v) {
    v.choice("planner", planner, {"analytic", "band"});
    v.number("trigger_ttc_s", trigger_ttc_s, 0.0, 30.0);
    v.number("trigger_distance_m", trigger_distance_m, 0.0, 50.0);
    v.nested("yield", yield);
  }
};

/// Minimal until the time to closest approach falls below trigger_ttc_s (~3 s), then yields.
struct LateFacilitatingParams {
  double trigger_ttc_s{3.0};
  MinimalParams minimal;
  YieldParams yield{0.6};
  template <class V>
  void visit(V& v) {
    v.number("trigger_ttc_s", trigger_ttc_s, 0.0, 30.0);
    v.nested("minimal", minimal);
    v.nested("yield", yield);
  }
};

/// Minimal until the robot's words reach it; then it does what a person told so would do
/// (docs/scenario-format.md, `responsive`): keeps to the other side when told the robot's side
/// (inform_offset_m), moves to the asked side when asked (yield.offset_m), each repeat adds
/// repeat_increment_m, and goes on past a robot that says it will wait. A person hears only
/// within hearing_range_m, complies with a request with probability compliance_request and with
/// a statement with compliance_statement (Nikolaidis et al. 2018: commands 100 %, state-conveying
/// statements 60 % adaptation), and starts acting after a log-normal reaction time (median
/// reaction_time_median_s, log-sd reaction_time_log_sd; T_react ≈ 1 s is our estimate: no
/// study of reaction to a robot's words in a corridor gives one).
/// The draws are the simulator's (Simulation, one stream per human), so the same seed gives
/// the same person.
struct ResponsiveParams {
  double reaction_time_median_s{1.0};  ///< from the end of the words to starting to move [s]
  double reaction_time_log_sd{0.3};    ///< log-normal shape: 90 % within ×/÷ 1.64 of the median
  double reaction_time_max_s{3.0};     ///< draws are cut here
  double hearing_range_m{10.0};        ///< farther than this the words are not heard [m]
  double compliance_request{0.9};      ///< P(moves | asked to move)
  double compliance_statement{0.6};    ///< P(keeps to the other side | told the robot's side)
  double inform_offset_m{0.4};         ///< shift when told the robot's side (modest) [m]
  double repeat_increment_m{0.2};      ///< each repeat or "more" to the same side adds this [m]
  MinimalParams minimal;
  YieldParams yield{0.75};  ///< offset_m: the shift when asked to move
  template <class V>
  void visit(V& v) {
    v.number("reaction_time_median_s", reaction_time_median_s, 0.0, 10.0);
    v.number("reaction_time_log_sd", reaction_time_log_sd, 0.0, 2.0);
    v.number("reaction_time_max_s", reaction_time_max_s, 0.0, 30.0);
    v.number("hearing_range_m", hearing_range_m, 0.0, 1000.0);
    v.number("compliance_request", compliance_request, 0.0, 1.0);
    v.number("compliance_statement", compliance_statement, 0.0, 1.0);
    v.number("inform_offset_m", inform_offset_m, 0.0, 3.0);
    v.number("repeat_increment_m", repeat_increment_m, 0.0, 2.0);
    v.nested("minimal", minimal);
    v.nested("yield", yield);
  }
};

/// The body check every behaviour but oblivious makes on its desired velocity (body_check.hpp):
/// a robot that is not coming at the human is treated as a wall is.
struct BodyCheckParams {
  /// Kept between the human's body and the robot's, and between its body and the wall, when it
  /// squeezes past a robot: people pass a still obstacle in a tight spot a few centimetres off.
  double squeeze_margin_m{0.05};
  /// Surface gap at which a human that cannot pass stops and waits (people stop about an arm's
  /// length short of someone blocking a corridor).
  double wait_gap_m{0.3};
  /// Starts steering round a robot in its way once the surface gap along its path is below this.
  double engage_distance_m{2.0};
  /// A robot moving towards the human faster than this is left to the model (the paper's
  /// behaviours react to an oncoming robot); slower, at rest or moving away, it is a body in the
  /// way.
  double rest_speed_m_s{0.1};
  /// Carrot distance of the steering round the robot (shorter when the robot is closer).
  double lookahead_m{0.8};
  /// Deceleration the human plans with when stopping short of the robot, as a fraction of its
  /// acceleration limit (the rest absorbs the discrete step).
  double brake_fraction{0.8};
  template <class V>
  void visit(V& v) {
    v.number("squeeze_margin_m", squeeze_margin_m, 0.0, 1.0);
    v.number("wait_gap_m", wait_gap_m, 0.0, 3.0);
    v.number("engage_distance_m", engage_distance_m, 0.0, 20.0);
    v.number("rest_speed_m_s", rest_speed_m_s, 0.0, 3.0);
    v.number("lookahead_m", lookahead_m, 0.1, 5.0);
    v.number("brake_fraction", brake_fraction, 0.1, 1.0);
  }
};

/// A person who stops for a while on the way and then goes on (to read a phone, to look
/// round): once it has walked after_m along its reference path it stands where it is for
/// duration_s, whatever the robot does, then walks on with its behaviour. Any behaviour but a
/// recorded one (scenario key `pause`); duration_s 0 = never pauses.
struct PauseParams {
  double after_m{0.0};     ///< [m] arc length along the reference path where it stops
  double duration_s{0.0};  ///< [s] how long it stands; 0 = no pause
  template <class V>
  void visit(V& v) {
    v.number("after_m", after_m, 0.0, 1000.0);
    v.number("duration_s", duration_s, 0.0, 600.0);
  }
};

/// When a person who yields of its own accord starts to (scenario key `avoidance_timing`).
enum class AvoidanceTiming : std::uint8_t {
  /// The behaviour's fixed trigger: facilitating at t_ca < trigger_ttc_s or a robot within
  /// trigger_distance_m, late_facilitating at t_ca < trigger_ttc_s, responsive at once (after
  /// its reaction time) on the robot's words.
  kTrigger,
  /// At an onset drawn per person from what real walkers do (RealisticOnsetParams):
  /// facilitating and late_facilitating start to yield once t_ca falls below it; a responsive
  /// person told the robot's side keeps to the other side from then on (a statement says where,
  /// not when), while a request is still acted on after the reaction time.
  kRealistic,
};
const char* toString(AvoidanceTiming t);
/// "trigger" or "realistic"; false when neither.
bool parseAvoidanceTiming(const std::string& s, AvoidanceTiming& out);

/// The onset of avoidance of real walkers in head-on encounters: seconds before the closest
/// approach at which a walker starts to step aside, log-normal. Fitted on the 306 walkers with an
/// onset among the 344 of the 172 real head-on pairs (test/data/pedestrians/headon_pairs.json,
/// `onset_a_t`/`onset_b_t`; UCY zara01 and students03): the log-mean and log-sd of the 288
/// onsets > 0 (the 18 at 0 are the 2.5 Hz annotation's, not a log-normal's), median
/// exp(0.538) = 1.71 s, log-sd 0.638; the largest measured onset, 6.8 s, cuts the draws. The
/// empirical quartiles are 1.2, 2.0 and 2.4 s.
struct RealisticOnsetParams {
  double median_s{1.71};  ///< [s] before the closest approach
  double log_sd{0.64};
  double max_s{6.8};  ///< [s] draws are cut here
  template <class V>
  void visit(V& v) {
    v.number("median_s", median_s, 0.0, 30.0);
    v.number("log_sd", log_sd, 0.0, 3.0);
    v.number("max_s", max_s, 0.0, 60.0);
  }
};

enum class BehaviourType : std::uint8_t {
  kMinimal,
  kOblivious,
  kSocialForce,
  kLateFacilitating,
  kResponsive,
  kFacilitating,
  kRecorded,  ///< replays a recorded track (recorded.hpp); ignores the robot
};

/// Scenario spelling of a type: minimal, oblivious, social_force, late_facilitating,
/// responsive, facilitating, recorded.
const char* toString(BehaviourType t);
/// Parses the scenario spelling; false when unknown.
bool parseBehaviourType(const std::string& s, BehaviourType& out);
/// All scenario spellings, for error messages.
std::vector<std::string> behaviourTypeNames();

/// A behaviour and its parameters; only the member matching type is used.
struct BehaviourConfig {
  BehaviourType type{BehaviourType::kMinimal};
  MinimalParams minimal;
  ObliviousParams oblivious;
  SocialForceParams social_force;
  LateFacilitatingParams late_facilitating;
  ResponsiveParams responsive;
  FacilitatingParams facilitating;
  RecordedParams recorded;
  BodyCheckParams body_check;  ///< every type but kOblivious and kRecorded
  PauseParams pause;           ///< every type but kRecorded
  /// [s] AvoidanceTiming::kRealistic: this person's onset, drawn by the simulator (time to
  /// closest approach below which it starts to yield; replaces the fixed trigger of
  /// facilitating and late_facilitating, and times a responsive person's keeping to a side it
  /// was told). nullopt: the behaviour's own trigger.
  std::optional<double> onset_s;
};

/// Plans a human's motion with an external planner (the planner-backed facilitating mode).
/// Returns nullopt when it has no plan this step; the behaviour then uses its analytic model.
class HumanPlannerAdapter {
 public:
  virtual ~HumanPlannerAdapter() = default;
  virtual std::optional<Velocity2> plan(const BehaviourContext& ctx) = 0;
};

/// Builds the adapter for one facilitating human (called once per human with planner: band).
using PlannerAdapterFactory =
    std::function<std::unique_ptr<HumanPlannerAdapter>(const FacilitatingParams&)>;

/// Creates a behaviour; every type but kOblivious and kRecorded with the body check
/// (body_check.hpp) on its desired velocity, every type but kRecorded with its pause
/// (PauseParams) when it has one. Throws std::invalid_argument for planner: band without
/// an adapter factory.
std::unique_ptr<HumanBehaviour> makeBehaviour(const BehaviourConfig& config,
                                              const PlannerAdapterFactory& planner_factory = {});

// ---- Helpers shared by behaviours and the tests (pure geometry on the reference path).

/// Point and unit tangent at arc length s_m along a path (clamped to its ends).
struct PathPoint {
  Eigen::Vector2d point{0.0, 0.0};
  Eigen::Vector2d tangent{1.0, 0.0};
};
PathPoint pointAtArc(const Path2& path, double s_m);
double pathLength(const Path2& path);

/// Constant-velocity prediction of the robot relative to a human walking its reference path.
struct Encounter {
  double distance_m{std::numeric_limits<double>::infinity()};   ///< centre distance now
  double gap_m{std::numeric_limits<double>::infinity()};        ///< surface gap now
  double t_closest_s{std::numeric_limits<double>::infinity()};  ///< time to closest approach
  bool closing{false};                                          ///< the distance is decreasing
  double along_m{0.0};          ///< robot position along the human's path direction (> 0 ahead)
  double robot_lateral_m{0.0};  ///< robot's predicted offset from the path at closest approach
  double crossing_arc_m{0.0};   ///< human's predicted arc length at closest approach
};
/// nullopt when the context has no robot or no path.
std::optional<Encounter> estimateEncounter(const BehaviourContext& ctx);

}  // namespace coopnav::sim
