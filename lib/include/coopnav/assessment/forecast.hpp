#pragma once
/// @file A forecast of cooperation: p_contributing, the probability that a person WILL have made
/// room (stepped >= 0.3 m aside, away from the robot) by the crossing, from what the track shows
/// up to now. The paper's CM (§II-C) measures the side step after it happened; real walkers start
/// to avoid only 0.8–2.4 s before the closest approach (test/data/pedestrians/README.md), later
/// than the paper's round-2 decision, so the decision needs a forecast, not a measure.
///
/// Model: logistic regression on standardised features (forecastFeatures()),
/// p = 1 / (1 + exp(−(b + Σ w_i (x_i − mean_i) / scale_i))), fitted by Newton's method (IRLS) on
/// the penalised log-likelihood −Σ [y log p + (1 − y) log(1 − p)] + ½ λ ||w||² (the bias is not
/// penalised). Reference: Hastie, Tibshirani, Friedman, "The Elements of Statistical Learning",
/// 2nd ed., §4.4.1 (IRLS) and §4.4.4 (L2-regularised logistic regression). Pure: no I/O, no clock.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace coopnav::assessment {

inline constexpr std::size_t kForecastFeatureCount = 6;

/// Names of the features, in order (the profile's YAML keys).
const std::array<const char*, kForecastFeatureCount>& forecastFeatureNames();

/// [m] below this lateral gap between the two, the side the robot is on is ambiguous (walkers
/// nearly in line): "away" is then the side the human has already moved to.
inline constexpr double kForecastInLineM = 0.1;
/// [s] span over which velocities are differenced (two samples of a 2.5 Hz tracker).
inline constexpr double kForecastVelocitySpanS = 0.8;
/// [s] the time to the crossing is clipped to [0, this] (beyond, "far": no more information).
inline constexpr double kForecastMaxTimeToCrossingS = 10.0;

/// One observation: time, human and robot positions (world frame).
struct ForecastObservation {
  double t_s{0.0};
  Eigen::Vector2d human_m{0.0, 0.0};
  Eigen::Vector2d robot_m{0.0, 0.0};
};

/// Features at the last observation. u = the human's initial heading (unit), origin = its position
/// at the interaction's start; s = the "away" sign: −sign(u × (p_r − p_h)) (the side opposite the
/// robot), or sign(d) when |u × (p_r − p_h)| < kForecastInLineM (ambiguous).
///  0 dev_away_m              s · d, d = u × (p_h − origin): how far it has already stepped away
///  1 lat_speed_away_m_s      s · (d(t) − d(t − span)) / Δt: how fast it is stepping away
///  2 speed_change_m_s        speed over the last span − speed over the first span
///  3 heading_change_away_rad s · atan2(u × v, u · v), v the last span's velocity
///  4 time_to_crossing_s      u·(p_r − p_h) / closing speed, in [0, 10] (10 when not closing)
///  5 lateral_gap_m           |u × (p_r − p_h)|: room already between their lines
struct ForecastFeatures {
  std::array<double, kForecastFeatureCount> x{};
  bool side_ambiguous{false};  ///< s came from the human's own displacement, not the robot's side
};

/// Features from observations in time order (nothing after "now", the last one). nullopt when
/// they span less than half of kForecastVelocitySpanS (no velocity yet) or the heading is zero.
std::optional<ForecastFeatures> forecastFeatures(const std::vector<ForecastObservation>& obs,
                                                 const Eigen::Vector2d& origin_m,
                                                 const Eigen::Vector2d& heading);

/// A fitted model (the profile): standardisation and coefficients.
struct ForecastModel {
  std::array<double, kForecastFeatureCount> mean{};
  std::array<double, kForecastFeatureCount> scale{1, 1, 1, 1, 1, 1};  ///< > 0
  std::array<double, kForecastFeatureCount> weight{};
  double bias{0.0};
  double l2{1.0};  ///< λ it was fitted with (documentation of the profile)
};

/// p_contributing in (0, 1).
double forecastProbability(const ForecastModel& m, const ForecastFeatures& f);

/// Result of fitLogisticL2.
struct LogisticFit {
  Eigen::VectorXd beta;  ///< [bias, w_1 .. w_k]
  int iterations{0};
  bool converged{false};
};

/// Newton/IRLS on the penalised log-likelihood (λ on every coefficient but the bias, column 0 of
/// the design being the implicit 1). X: n × k features (not including the intercept), y in {0, 1}.
/// Converged when the largest Newton step component is below tol. Throws std::invalid_argument on
/// mismatched sizes, an empty X, λ < 0 or y not 0/1.
LogisticFit fitLogisticL2(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, double l2,
                          int max_iterations = 100, double tol = 1e-10);

/// Standardises (mean, population standard deviation; a constant feature gets scale 1) and fits.
ForecastModel fitForecastModel(const std::vector<ForecastFeatures>& features,
                               const std::vector<int>& labels, double l2);

/// p_contributing of one human over an interaction, as a daemon publishes it: started with the
/// human's position and heading at the START (the reference path's start and direction), fed its
/// observations; keeps only what the features read (the first velocity span and the last one), so
/// memory is bounded whatever the interaction's length.
class CooperationForecaster {
 public:
  explicit CooperationForecaster(const ForecastModel& model = {}) : model_(model) {}
  /// Starts an interaction (clears the observations).
  void start(const Eigen::Vector2d& origin_m, const Eigen::Vector2d& heading);
  /// Ends it: later observations are ignored, the last probability stays.
  void stop() { started_ = false; }
  /// An observation; ignored before start(), after stop() and when not later than the last one.
  void observe(double t_s, const Eigen::Vector2d& human_m, const Eigen::Vector2d& robot_m);
  /// In (0, 1); NaN while unknown (no interaction, or less than half a velocity span seen).
  double pContributing() const { return p_; }
  /// Features behind pContributing() (nullopt while unknown).
  const std::optional<ForecastFeatures>& features() const { return features_; }

 private:
  ForecastModel model_;
  bool started_{false};
  Eigen::Vector2d origin_m_{0.0, 0.0};
  Eigen::Vector2d heading_{1.0, 0.0};
  std::vector<ForecastObservation> first_;  // from the start to the first one a span later
  std::deque<ForecastObservation> recent_;  // the last span, and the one just before it
  std::optional<ForecastFeatures> features_;
  double p_{std::numeric_limits<double>::quiet_NaN()};
};

}  // namespace coopnav::assessment
