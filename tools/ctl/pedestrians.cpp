#include "pedestrians.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "../population/stats.hpp"
#include "json.hpp"

namespace coopnav::ctl {
namespace {

using assessment::PathAssessorConfig;
using assessment::PathRecorder;
using assessment::SideRule;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Annotated times are multiples of 0.4 s written as decimals: compare them with a tolerance far
// below the sample spacing, not exactly.
constexpr double kTimeTolS = 1e-6;
// [m] long enough for any encounter here (8 m apart at t0, a few seconds to the crossing).
constexpr double kReferenceLengthM = 50.0;

// ---- reading ----------------------------------------------------------------------------------

[[noreturn]] void fail(const std::string& where, const std::string& reason) {
  throw std::runtime_error(where + ": " + reason);
}

const Json& need(const Json& obj, const std::string& key, const std::string& where) {
  if (!obj.is_object()) fail(where, "not an object");
  const auto it = obj.find(key);
  if (it == obj.end()) fail(where, "missing \"" + key + "\"");
  return *it;
}

double finiteNumber(const Json& v, const std::string& where) {
  if (!v.is_number()) fail(where, "not a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(where, "not a finite number");
  return d;
}

std::vector<double> numberArray(const Json& v, const std::string& where) {
  if (!v.is_array()) fail(where, "not an array");
  std::vector<double> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    out.push_back(finiteNumber(v[i], where + "[" + std::to_string(i) + "]"));
  return out;
}

void readHeading(const Json& v, double (&u)[2], const std::string& where) {
  const auto h = numberArray(v, where);
  if (h.size() != 2) fail(where, "heading must have 2 numbers");
  const double n = std::hypot(h[0], h[1]);
  if (!(n > 0.5)) fail(where, "heading is not a unit vector");
  // Stored rounded to 1e-6: renormalise so lateral distances are exact metres.
  u[0] = h[0] / n;
  u[1] = h[1] / n;
}

PedestrianTrack readTrack(const Json& v, const std::string& where) {
  PedestrianTrack tr;
  const Json& id = need(v, "id", where);
  if (!id.is_number_integer()) fail(where + ".id", "not an integer");
  tr.id = id.get<long>();
  tr.t_s = numberArray(need(v, "t", where), where + ".t");
  tr.x_m = numberArray(need(v, "x", where), where + ".x");
  tr.y_m = numberArray(need(v, "y", where), where + ".y");
  if (tr.t_s.size() != tr.x_m.size() || tr.t_s.size() != tr.y_m.size())
    fail(where, "arrays t, x, y of unequal length (" + std::to_string(tr.t_s.size()) + ", " +
                    std::to_string(tr.x_m.size()) + ", " + std::to_string(tr.y_m.size()) + ")");
  if (tr.t_s.size() < 2) fail(where, "fewer than 2 samples");
  for (std::size_t i = 1; i < tr.t_s.size(); ++i)
    if (!(tr.t_s[i] > tr.t_s[i - 1])) fail(where + ".t", "times not strictly increasing");
  return tr;
}

bool covers(const PedestrianTrack& tr, double t_s) {
  return t_s >= tr.t_s.front() - kTimeTolS && t_s <= tr.t_s.back() + kTimeTolS;
}

// Position at t_s, linear between the bracketing samples; nullopt outside the track.
std::optional<Eigen::Vector2d> positionAt(const PedestrianTrack& tr, double t_s) {
  if (!covers(tr, t_s)) return std::nullopt;
  const auto it = std::lower_bound(tr.t_s.begin(), tr.t_s.end(), t_s - kTimeTolS);
  const auto i = static_cast<std::size_t>(it - tr.t_s.begin());
  if (i >= tr.t_s.size()) return Eigen::Vector2d(tr.x_m.back(), tr.y_m.back());
  if (i == 0 || std::abs(tr.t_s[i] - t_s) <= kTimeTolS)
    return Eigen::Vector2d(tr.x_m[i], tr.y_m[i]);
  const double s = (t_s - tr.t_s[i - 1]) / (tr.t_s[i] - tr.t_s[i - 1]);
  return Eigen::Vector2d(tr.x_m[i - 1] + s * (tr.x_m[i] - tr.x_m[i - 1]),
                         tr.y_m[i - 1] + s * (tr.y_m[i] - tr.y_m[i - 1]));
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// ---- replay -----------------------------------------------------------------------------------

struct Replay {
  WalkerResult walker;
  std::vector<double> ca_m;  // interaction CA (for γ sweeps without replaying)
};

// One walker as the human, the other as the robot.
Replay replayWalker(const PedestrianPair& p, std::size_t pair_index, bool a_is_human,
                    const PathAssessorConfig& config) {
  const PedestrianTrack& human = a_is_human ? p.a : p.b;
  const PedestrianTrack& robot = a_is_human ? p.b : p.a;
  const double* h = a_is_human ? p.heading_a : p.heading_b;
  const Eigen::Vector2d u(h[0], h[1]);

  Replay r;
  WalkerResult& w = r.walker;
  w.pair_index = pair_index;
  w.ds = p.ds;
  w.id = human.id;
  w.other_id = robot.id;

  // Loading checked that both tracks cover [t0_s, t_cross_s].
  const Eigen::Vector2d h0 = *positionAt(human, p.t0_s);
  const Eigen::Vector2d hc = *positionAt(human, p.t_cross_s);
  const Eigen::Vector2d rc = *positionAt(robot, p.t_cross_s);
  w.lateral_m = cross(u, hc - h0);
  w.other_offset_m = cross(u, rc - hc);
  w.dev_away_m = w.other_offset_m > 0.0   ? -w.lateral_m
                 : w.other_offset_m < 0.0 ? w.lateral_m
                                          : std::abs(w.lateral_m);

  PathRecorder rec(config);
  rec.start(p.t0_s, Path2{h0, h0 + kReferenceLengthM * u});
  for (std::size_t i = 0; i < human.t_s.size(); ++i) {
    const double t = human.t_s[i];
    if (t < p.t0_s - kTimeTolS || t > p.t_cross_s + kTimeTolS) continue;
    const auto rp = positionAt(robot, t);
    if (!rp) continue;
    rec.observe(t, Eigen::Vector2d(human.x_m[i], human.y_m[i]), *rp);
  }
  rec.stop(p.t_cross_s);
  const auto snap = rec.snapshot();
  w.cm_m = snap.cm_interaction_m;
  w.samples = snap.interaction_samples;
  r.ca_m = rec.interactionCa();
  return r;
}

std::vector<Replay> replayAll(const std::vector<PedestrianPair>& pairs,
                              const PathAssessorConfig& config) {
  std::vector<Replay> out;
  out.reserve(2 * pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    out.push_back(replayWalker(pairs[i], i, true, config));
    out.push_back(replayWalker(pairs[i], i, false, config));
  }
  return out;
}

double ratio(std::size_t num, std::size_t den) {
  return den == 0 ? kNaN : static_cast<double>(num) / static_cast<double>(den);
}

// Fills the metrics of e from e.walkers (pairs as consecutive walkers a, b) and e.config.tau_m.
void score(PedestrianEvaluation& e) {
  const double tau_m = e.config.tau_m;
  e.pairs_judged = e.pairs_ranked_right = e.walkers_judged = 0;
  e.true_positive = e.false_positive = e.false_negative = e.true_negative = 0;
  for (std::size_t i = 0; i + 1 < e.walkers.size(); i += 2) {
    const auto& wa = e.walkers[i];
    const auto& wb = e.walkers[i + 1];
    if (!wa.cm_m || !wb.cm_m) continue;
    if (std::abs(wa.dev_away_m - wb.dev_away_m) < kRankingMinDifferenceM) continue;
    ++e.pairs_judged;
    const bool a_moved_more = wa.dev_away_m > wb.dev_away_m;
    if (a_moved_more ? *wa.cm_m > *wb.cm_m : *wb.cm_m > *wa.cm_m) ++e.pairs_ranked_right;
  }
  std::vector<double> pos_cm;
  std::vector<double> neg_cm;
  for (const auto& w : e.walkers) {
    if (!w.cm_m) continue;
    ++e.walkers_judged;
    const bool truth = w.dev_away_m >= kStepAwayTruthM;
    const bool said = *w.cm_m > tau_m;
    (truth ? pos_cm : neg_cm).push_back(*w.cm_m);
    if (said && truth) ++e.true_positive;
    if (said && !truth) ++e.false_positive;
    if (!said && truth) ++e.false_negative;
    if (!said && !truth) ++e.true_negative;
  }
  e.ranking = ratio(e.pairs_ranked_right, e.pairs_judged);
  e.agreement = ratio(e.true_positive + e.true_negative, e.walkers_judged);
  e.auc = population::mannWhitneyAuc(pos_cm, neg_cm);
}

CalibrationScore scoreOf(const PedestrianEvaluation& e) {
  CalibrationScore s;
  s.ranking = e.ranking;
  s.agreement = e.agreement;
  s.objective = 0.5 * ((std::isnan(e.ranking) ? 0.0 : e.ranking) +
                       (std::isnan(e.agreement) ? 0.0 : e.agreement));
  return s;
}

struct Fit {
  CalibrationSetting setting;
  CalibrationScore score;
};

// Grid search on `pairs`: CA is replayed once per side rule (γ and τ do not change it).
Fit gridSearch(const std::vector<PedestrianPair>& pairs, const PathAssessorConfig& base) {
  const SideRule rules[] = {SideRule::kPathSide, SideRule::kHumanSide};
  std::vector<std::vector<Replay>> replays;
  for (const SideRule rule : rules) {
    PathAssessorConfig c = base;
    c.side_rule = rule;
    replays.push_back(replayAll(pairs, c));
  }
  Fit best;
  bool have = false;
  for (const double gamma_per_s : calibrationGammasPerS()) {
    for (std::size_t r = 0; r < 2; ++r) {
      PedestrianEvaluation e;
      e.config = settingConfig({gamma_per_s, rules[r], 0.0}, base);
      for (const auto& rep : replays[r]) {
        e.walkers.push_back(rep.walker);
        e.walkers.back().cm_m = assessment::discountedMean(rep.ca_m, e.config.gamma);
      }
      for (const double tau_m : calibrationTausM()) {
        e.config.tau_m = tau_m;
        score(e);
        const CalibrationScore s = scoreOf(e);
        // Within one γ and side rule, a tie goes to the larger τ: where the walkers cannot tell
        // the thresholds apart, the verdict that claims cooperation less often (the robot then
        // keeps its own margin rather than count on the human).
        const bool same_curve =
            have && best.setting.gamma_per_s == gamma_per_s && best.setting.side_rule == rules[r];
        if (!have || s.objective > best.score.objective ||
            (same_curve && s.objective == best.score.objective)) {
          best = {{gamma_per_s, rules[r], tau_m}, s};
          have = true;
        }
      }
    }
  }
  return best;
}

CalibrationScore evaluateSetting(const std::vector<PedestrianPair>& pairs,
                                 const CalibrationSetting& s, const PathAssessorConfig& base) {
  return scoreOf(evaluateWalkers(pairs, settingConfig(s, base)));
}

std::string fmt(const char* format, double v) {
  if (std::isnan(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string settingText(const CalibrationSetting& s) {
  return "gamma_per_s " + fmt("%.4f", s.gamma_per_s) + ", side_rule " +
         assessment::toString(s.side_rule) + ", tau " + fmt("%.3f", s.tau_m) + " m";
}

std::string scoreText(const CalibrationScore& s) {
  return "ranking " + fmt("%.3f", s.ranking) + ", agreement " + fmt("%.3f", s.agreement) +
         ", objective " + fmt("%.3f", s.objective);
}

}  // namespace

std::vector<PedestrianPair> loadPedestrianPairs(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot read");
  std::stringstream ss;
  ss << in.rdbuf();
  Json doc;
  try {
    doc = parseJson(ss.str());
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  const Json& schema = need(doc, "schema", path);
  if (!schema.is_string() || schema.get<std::string>() != kPedestrianPairsSchema)
    fail(path, std::string("schema is not \"") + kPedestrianPairsSchema + "\"");
  const Json& jp = need(doc, "pairs", path);
  if (!jp.is_array()) fail(path + ": pairs", "not an array");
  std::vector<PedestrianPair> pairs;
  pairs.reserve(jp.size());
  for (std::size_t i = 0; i < jp.size(); ++i) {
    const std::string where = path + ": pairs[" + std::to_string(i) + "]";
    const Json& j = jp[i];
    PedestrianPair p;
    const Json& ds = need(j, "ds", where);
    if (!ds.is_string()) fail(where + ".ds", "not a string");
    p.ds = ds.get<std::string>();
    p.t0_s = finiteNumber(need(j, "t0_s", where), where + ".t0_s");
    p.t_cross_s = finiteNumber(need(j, "t_cross_s", where), where + ".t_cross_s");
    if (!(p.t_cross_s > p.t0_s)) fail(where, "t_cross_s is not after t0_s");
    readHeading(need(j, "heading_a", where), p.heading_a, where + ".heading_a");
    readHeading(need(j, "heading_b", where), p.heading_b, where + ".heading_b");
    p.a = readTrack(need(j, "traj_a", where), where + ".traj_a");
    p.b = readTrack(need(j, "traj_b", where), where + ".traj_b");
    for (const auto* tr : {&p.a, &p.b})
      if (!covers(*tr, p.t0_s) || !covers(*tr, p.t_cross_s))
        fail(where, "track " + std::to_string(tr->id) + " does not cover [t0_s, t_cross_s]");
    pairs.push_back(std::move(p));
  }
  return pairs;
}

PedestrianEvaluation evaluateWalkers(const std::vector<PedestrianPair>& pairs,
                                     const PathAssessorConfig& config) {
  PedestrianEvaluation e;
  e.config = config;
  for (auto& r : replayAll(pairs, config)) e.walkers.push_back(std::move(r.walker));
  score(e);
  return e;
}

double gammaPerSample(double gamma_per_s, double sample_period_s) {
  return std::pow(gamma_per_s, sample_period_s);
}

std::vector<double> calibrationGammasPerS() {
  // 0.98^10: the paper's γ 0.98 per 0.1 s sample, per second.
  return {0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, std::pow(0.98, 10), 0.9, 1.0};
}

std::vector<double> calibrationTausM() {
  std::vector<double> taus;
  // Integer steps, not repeated += 0.025, so the grid values are the decimals they print as.
  for (int i = 0; i <= 22; ++i) taus.push_back(0.05 + 0.025 * i);
  return taus;
}

PathAssessorConfig settingConfig(const CalibrationSetting& setting,
                                 const PathAssessorConfig& base) {
  PathAssessorConfig c = base;
  c.gamma = gammaPerSample(setting.gamma_per_s, base.sample_period_s);
  c.side_rule = setting.side_rule;
  c.tau_m = setting.tau_m;
  return c;
}

CalibrationResult calibrate(const std::vector<PedestrianPair>& pairs,
                            const PathAssessorConfig& base) {
  CalibrationResult r;
  r.paper_setting = {std::pow(0.98, 10), SideRule::kPathSide, 0.4};
  std::vector<std::string> sequences;
  for (const auto& p : pairs)
    if (std::find(sequences.begin(), sequences.end(), p.ds) == sequences.end())
      sequences.push_back(p.ds);
  // Leave-one-sequence-out: pairs of one sequence share walkers and a scene, so a random split
  // would score on near-copies of what was fitted.
  if (sequences.size() > 1) {
    for (const auto& ds : sequences) {
      std::vector<PedestrianPair> fit_pairs;
      std::vector<PedestrianPair> held_pairs;
      for (const auto& p : pairs) (p.ds == ds ? held_pairs : fit_pairs).push_back(p);
      CalibrationFold f;
      f.held_out_ds = ds;
      f.fit_pairs = fit_pairs.size();
      f.held_out_pairs = held_pairs.size();
      const Fit fit = gridSearch(fit_pairs, base);
      f.setting = fit.setting;
      f.fit = fit.score;
      f.held_out = evaluateSetting(held_pairs, f.setting, base);
      f.paper_held_out = evaluateSetting(held_pairs, r.paper_setting, base);
      r.folds.push_back(std::move(f));
    }
  }
  const Fit all = gridSearch(pairs, base);
  r.final_setting = all.setting;
  r.final_score = all.score;
  r.paper_score = evaluateSetting(pairs, r.paper_setting, base);
  return r;
}

std::string formatPedestrianEvaluation(const PedestrianEvaluation& e, double gamma_per_s) {
  std::ostringstream o;
  o << "settings: gamma " << fmt("%.6f", e.config.gamma) << " per "
    << fmt("%.3f", e.config.sample_period_s) << " s sample (" << fmt("%.4f", gamma_per_s)
    << " per s), tau " << fmt("%.3f", e.config.tau_m) << " m, side_rule "
    << assessment::toString(e.config.side_rule) << "\n";
  o << "walkers " << e.walkers.size() << " (with a CM " << e.walkers_judged << ")\n";
  o << "pairs judged " << e.pairs_judged
    << " (|dev_away_a - dev_away_b| >= " << fmt("%.2f", kRankingMinDifferenceM)
    << " m), ranked right " << e.pairs_ranked_right << "\n";
  o << "ranking " << fmt("%.3f", e.ranking) << "\n";
  o << "agreement " << fmt("%.3f", e.agreement)
    << " ((CM > tau) == (dev_away >= " << fmt("%.2f", kStepAwayTruthM) << " m))\n";
  o << "auc " << fmt("%.3f", e.auc) << "\n";
  o << "confusion: TP " << e.true_positive << ", FP " << e.false_positive << ", FN "
    << e.false_negative << ", TN " << e.true_negative << "\n";
  o << "RESULT pedestrians_pair_ranking " << fmt("%.4f", e.ranking) << "\n";
  o << "RESULT pedestrians_is_contributing_agreement " << fmt("%.4f", e.agreement) << "\n";
  return o.str();
}

std::string formatCalibration(const CalibrationResult& r) {
  std::ostringstream o;
  o << "leave-one-sequence-out folds:\n";
  for (const auto& f : r.folds) {
    o << "  held out " << f.held_out_ds << " (" << f.held_out_pairs << " pairs; fit on "
      << f.fit_pairs << "): " << settingText(f.setting) << "\n";
    o << "    fit      " << scoreText(f.fit) << "\n";
    o << "    held out " << scoreText(f.held_out) << "\n";
    o << "    paper    " << scoreText(f.paper_held_out) << "\n";
  }
  o << "final fit (all pairs): " << settingText(r.final_setting) << "\n";
  o << "  calibrated " << scoreText(r.final_score) << "\n";
  o << "  paper      " << scoreText(r.paper_score) << " (" << settingText(r.paper_setting) << ")\n";
  o << "RESULT pedestrians_calibrated_gamma_per_s " << fmt("%.4f", r.final_setting.gamma_per_s)
    << "\n";
  o << "RESULT pedestrians_calibrated_side_rule " << assessment::toString(r.final_setting.side_rule)
    << "\n";
  o << "RESULT pedestrians_calibrated_tau_m " << fmt("%.3f", r.final_setting.tau_m) << "\n";
  return o.str();
}

}  // namespace coopnav::ctl
