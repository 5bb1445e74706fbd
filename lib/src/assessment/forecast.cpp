#include "coopnav/assessment/forecast.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace coopnav::assessment {
namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Index of the last observation at or before t_s (at least 0).
std::size_t lastAtOrBefore(const std::vector<ForecastObservation>& obs, double t_s) {
  std::size_t k = 0;
  while (k + 1 < obs.size() && obs[k + 1].t_s <= t_s + 1e-9) ++k;
  return k;
}

// Numerically safe logistic function.
double sigmoid(double z) {
  if (z >= 0.0) return 1.0 / (1.0 + std::exp(-z));
  const double e = std::exp(z);
  return e / (1.0 + e);
}

}  // namespace

const std::array<const char*, kForecastFeatureCount>& forecastFeatureNames() {
  static const std::array<const char*, kForecastFeatureCount> names{
      "dev_away_m",         "lat_speed_away_m_s", "speed_change_m_s", "heading_change_away_rad",
      "time_to_crossing_s", "lateral_gap_m"};
  return names;
}

std::optional<ForecastFeatures> forecastFeatures(const std::vector<ForecastObservation>& obs,
                                                 const Eigen::Vector2d& origin_m,
                                                 const Eigen::Vector2d& heading) {
  if (obs.size() < 2) return std::nullopt;
  const double n = heading.norm();
  if (!(n > 0.0)) return std::nullopt;
  const Eigen::Vector2d u = heading / n;
  const ForecastObservation& now = obs.back();
  const ForecastObservation& past = obs[lastAtOrBefore(obs, now.t_s - kForecastVelocitySpanS)];
  const double dt = now.t_s - past.t_s;
  if (!(dt >= 0.5 * kForecastVelocitySpanS)) return std::nullopt;
  const ForecastObservation& first = obs.front();
  // The first span: from the first observation to the first one at least a span later (or now).
  std::size_t j = 0;
  while (j + 1 < obs.size() && obs[j].t_s < first.t_s + kForecastVelocitySpanS - 1e-9) ++j;
  const double dt_first = obs[j].t_s - first.t_s;
  if (!(dt_first > 0.0)) return std::nullopt;

  const Eigen::Vector2d rel = now.robot_m - now.human_m;
  const double gap = cross(u, rel);
  const double d = cross(u, now.human_m - origin_m);
  ForecastFeatures f;
  double s = 0.0;
  if (std::abs(gap) >= kForecastInLineM) {
    s = gap > 0.0 ? -1.0 : 1.0;
  } else {
    // Nearly in line: which side the robot is on is noise; the side the human already moved to
    // is the one it will pass on.
    f.side_ambiguous = true;
    s = d >= 0.0 ? 1.0 : -1.0;
  }
  const Eigen::Vector2d v_h = (now.human_m - past.human_m) / dt;
  const Eigen::Vector2d v_r = (now.robot_m - past.robot_m) / dt;
  const Eigen::Vector2d v_first = (obs[j].human_m - first.human_m) / dt_first;
  const double d_past = cross(u, past.human_m - origin_m);

  f.x[0] = s * d;
  f.x[1] = s * (d - d_past) / dt;
  f.x[2] = v_h.norm() - v_first.norm();
  f.x[3] = v_h.norm() > 0.0 ? s * std::atan2(cross(u, v_h), u.dot(v_h)) : 0.0;
  const double dist = rel.norm();
  const double closing = dist > 0.0 ? -rel.dot(v_r - v_h) / dist : 0.0;
  const double along = std::max(0.0, u.dot(rel));
  f.x[4] = closing > along / kForecastMaxTimeToCrossingS
               ? std::clamp(along / closing, 0.0, kForecastMaxTimeToCrossingS)
               : kForecastMaxTimeToCrossingS;
  f.x[5] = std::abs(gap);
  return f;
}

double forecastProbability(const ForecastModel& m, const ForecastFeatures& f) {
  double z = m.bias;
  for (std::size_t i = 0; i < kForecastFeatureCount; ++i)
    z += m.weight[i] * (f.x[i] - m.mean[i]) / m.scale[i];
  return sigmoid(z);
}

LogisticFit fitLogisticL2(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, double l2,
                          int max_iterations, double tol) {
  const Eigen::Index n = X.rows();
  const Eigen::Index k = X.cols();
  if (n == 0) throw std::invalid_argument("fitLogisticL2: no rows");
  if (y.size() != n) throw std::invalid_argument("fitLogisticL2: y and X differ in rows");
  if (!(l2 >= 0.0)) throw std::invalid_argument("fitLogisticL2: l2 must be >= 0");
  for (Eigen::Index i = 0; i < n; ++i)
    if (y[i] != 0.0 && y[i] != 1.0) throw std::invalid_argument("fitLogisticL2: y not 0/1");
  Eigen::MatrixXd A(n, k + 1);
  A.col(0).setOnes();
  A.rightCols(k) = X;
  Eigen::VectorXd penalty = Eigen::VectorXd::Constant(k + 1, l2);
  penalty[0] = 0.0;

  LogisticFit fit;
  fit.beta = Eigen::VectorXd::Zero(k + 1);
  for (int it = 0; it < max_iterations; ++it) {
    const Eigen::VectorXd z = A * fit.beta;
    Eigen::VectorXd p(n);
    Eigen::VectorXd w(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      p[i] = sigmoid(z[i]);
      // A floor keeps the Hessian positive definite on separable data (then λ bounds β).
      w[i] = std::max(p[i] * (1.0 - p[i]), 1e-12);
    }
    const Eigen::VectorXd grad = A.transpose() * (p - y) + penalty.cwiseProduct(fit.beta);
    Eigen::MatrixXd H = A.transpose() * w.asDiagonal() * A;
    H.diagonal() += penalty;
    const Eigen::VectorXd step = H.ldlt().solve(grad);
    fit.beta -= step;
    fit.iterations = it + 1;
    if (step.cwiseAbs().maxCoeff() < tol) {
      fit.converged = true;
      break;
    }
  }
  return fit;
}

ForecastModel fitForecastModel(const std::vector<ForecastFeatures>& features,
                               const std::vector<int>& labels, double l2) {
  if (features.empty() || features.size() != labels.size())
    throw std::invalid_argument("fitForecastModel: features and labels empty or of unequal size");
  const auto n = static_cast<Eigen::Index>(features.size());
  const auto k = static_cast<Eigen::Index>(kForecastFeatureCount);
  ForecastModel m;
  m.l2 = l2;
  Eigen::MatrixXd X(n, k);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index c = 0; c < k; ++c)
      X(i, c) = features[static_cast<std::size_t>(i)].x[static_cast<std::size_t>(c)];
    y[i] = labels[static_cast<std::size_t>(i)] != 0 ? 1.0 : 0.0;
  }
  for (Eigen::Index c = 0; c < k; ++c) {
    const double mean = X.col(c).mean();
    const double sd = std::sqrt((X.col(c).array() - mean).square().mean());
    const auto ci = static_cast<std::size_t>(c);
    m.mean[ci] = mean;
    m.scale[ci] = sd > 1e-12 ? sd : 1.0;
    X.col(c) = (X.col(c).array() - mean) / m.scale[ci];
  }
  const LogisticFit fit = fitLogisticL2(X, y, l2);
  m.bias = fit.beta[0];
  for (std::size_t c = 0; c < kForecastFeatureCount; ++c)
    m.weight[c] = fit.beta[static_cast<Eigen::Index>(c) + 1];
  return m;
}

void CooperationForecaster::start(const Eigen::Vector2d& origin_m, const Eigen::Vector2d& heading) {
  started_ = true;
  origin_m_ = origin_m;
  heading_ = heading;
  first_.clear();
  recent_.clear();
  features_.reset();
  p_ = std::numeric_limits<double>::quiet_NaN();
}

void CooperationForecaster::observe(double t_s, const Eigen::Vector2d& human_m,
                                    const Eigen::Vector2d& robot_m) {
  if (!started_) return;
  if (!recent_.empty() && !(t_s > recent_.back().t_s)) return;
  const ForecastObservation o{t_s, human_m, robot_m};
  // forecastFeatures() reads the first observation, the first one a span after it, the last one
  // at or before now − span, and now.
  if (first_.empty() || first_.back().t_s < first_.front().t_s + kForecastVelocitySpanS - 1e-9)
    first_.push_back(o);
  recent_.push_back(o);
  while (recent_.size() > 2 && recent_[1].t_s <= t_s - kForecastVelocitySpanS + 1e-9)
    recent_.pop_front();
  std::vector<ForecastObservation> obs(first_.begin(), first_.end());
  for (const auto& r : recent_)
    if (r.t_s > obs.back().t_s) obs.push_back(r);
  features_ = forecastFeatures(obs, origin_m_, heading_);
  p_ = features_ ? forecastProbability(model_, *features_)
                 : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace coopnav::assessment
