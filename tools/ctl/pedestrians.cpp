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

// One walker as the human, the other as the robot.
WalkerRun planWalkerRun(const PedestrianPair& p, std::size_t pair_index, bool a_is_human,
                        const WindowSetting& window) {
  const PedestrianTrack& human = a_is_human ? p.a : p.b;
  const PedestrianTrack& robot = a_is_human ? p.b : p.a;
  const double* h = a_is_human ? p.heading_a : p.heading_b;
  const Eigen::Vector2d u(h[0], h[1]);

  WalkerRun run;
  WalkerResult& w = run.walker;
  w.pair_index = pair_index;
  w.ds = p.ds;
  w.id = human.id;
  w.other_id = robot.id;
  w.t_cross_s = p.t_cross_s;

  // Loading checked that both tracks cover [t0_s, t_cross_s].
  const Eigen::Vector2d h0 = *positionAt(human, p.t0_s);
  const Eigen::Vector2d hc = *positionAt(human, p.t_cross_s);
  const Eigen::Vector2d rc = *positionAt(robot, p.t_cross_s);
  w.lateral_m = cross(u, hc - h0);
  w.other_offset_m = cross(u, rc - hc);
  w.dev_away_m = w.other_offset_m > 0.0   ? -w.lateral_m
                 : w.other_offset_m < 0.0 ? w.lateral_m
                                          : std::abs(w.lateral_m);
  run.reference = Path2{h0, h0 + kReferenceLengthM * u};
  run.stop_t_s = p.t_cross_s;

  for (std::size_t i = 0; i < human.t_s.size(); ++i) {
    const double t = human.t_s[i];
    if (t < p.t0_s - kTimeTolS || t > p.t_cross_s + kTimeTolS) continue;
    const auto rp = positionAt(robot, t);
    if (!rp) continue;
    run.observations.push_back({t, Eigen::Vector2d(human.x_m[i], human.y_m[i]), *rp});
  }

  std::vector<double> ts;
  std::vector<Eigen::Vector2d> ps;
  for (const auto& o : run.observations) {
    ts.push_back(o.t_s);
    ps.push_back(o.human_m);
  }
  const auto onset = detectAvoidanceOnset(ts, ps, h0, u);
  if (onset) w.onset_t_s = onset->onset_t_s;

  // The first observation at or before `t_s` (at least the first: the human must be known).
  const auto lastAtOrBefore = [&](double t_s) {
    std::size_t k = 0;
    while (k + 1 < run.observations.size() && run.observations[k + 1].t_s <= t_s + kTimeTolS) ++k;
    return k;
  };
  switch (window.kind) {
    case WindowKind::kRound1:
      w.window_start_s = p.t0_s;
      run.start_after = lastAtOrBefore(p.t0_s);
      break;
    case WindowKind::kLead:
      w.window_start_s = std::max(p.t0_s, p.t_cross_s - window.lead_s);
      run.start_after = lastAtOrBefore(w.window_start_s);
      break;
    case WindowKind::kOnset:
      if (onset) {
        w.window_start_s = onset->onset_t_s;
        run.start_after = onset->detected_index;
      } else {
        w.window_start_s = p.t0_s;
        run.start_after = lastAtOrBefore(p.t0_s);
      }
      break;
  }
  return run;
}

struct Replay {
  WalkerResult walker;
  std::vector<double> ca_m;  // interaction CA (for γ sweeps without replaying)
};

std::vector<Replay> replayAll(const std::vector<PedestrianPair>& pairs,
                              const PathAssessorConfig& config, const WindowSetting& window) {
  std::vector<Replay> out;
  out.reserve(2 * pairs.size());
  for (auto& run : planWalkerRuns(pairs, window)) {
    RunOutcome o = replayRun(run, config);
    Replay r;
    r.walker = std::move(run.walker);
    r.walker.cm_m = o.cm_m;
    r.walker.samples = o.samples;
    r.ca_m = std::move(o.ca_m);
    out.push_back(std::move(r));
  }
  return out;
}

double ratio(std::size_t num, std::size_t den) {
  return den == 0 ? kNaN : static_cast<double>(num) / static_cast<double>(den);
}

}  // namespace

void scoreEvaluation(PedestrianEvaluation& e) {
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

namespace {

CalibrationScore scoreOf(const PedestrianEvaluation& e) {
  CalibrationScore s;
  s.ranking = e.ranking;
  s.agreement = e.agreement;
  s.objective = 0.5 * ((std::isnan(e.ranking) ? 0.0 : e.ranking) +
                       (std::isnan(e.agreement) ? 0.0 : e.agreement));
  s.auc = e.auc;
  return s;
}

struct Fit {
  CalibrationSetting setting;
  CalibrationScore score;
};

// Grid search on `pairs`, per window of calibrationWindows() (in that order): CA is replayed once
// per window and side rule (γ and τ do not change it).
std::vector<Fit> gridSearchPerWindow(const std::vector<PedestrianPair>& pairs,
                                     const PathAssessorConfig& base) {
  const SideRule rules[] = {SideRule::kPathSide, SideRule::kHumanSide};
  std::vector<Fit> fits;
  for (const WindowSetting& window : calibrationWindows()) {
    std::vector<std::vector<Replay>> replays;
    for (const SideRule rule : rules) {
      PathAssessorConfig c = base;
      c.side_rule = rule;
      replays.push_back(replayAll(pairs, c, window));
    }
    Fit best;
    bool have = false;
    for (const double gamma_per_s : calibrationGammasPerS()) {
      for (std::size_t r = 0; r < 2; ++r) {
        PedestrianEvaluation e;
        e.config = settingConfig({gamma_per_s, rules[r], 0.0, window}, base);
        for (const auto& rep : replays[r]) {
          e.walkers.push_back(rep.walker);
          e.walkers.back().cm_m = assessment::discountedMean(rep.ca_m, e.config.gamma);
        }
        for (const double tau_m : calibrationTausM()) {
          e.config.tau_m = tau_m;
          scoreEvaluation(e);
          const CalibrationScore s = scoreOf(e);
          // Within one γ and side rule, a tie goes to the larger τ: where the walkers cannot
          // tell the thresholds apart, the verdict that claims cooperation less often (the robot
          // then keeps its own margin rather than count on the human).
          const bool same_curve =
              have && best.setting.gamma_per_s == gamma_per_s && best.setting.side_rule == rules[r];
          if (!have || s.objective > best.score.objective ||
              (same_curve && s.objective == best.score.objective)) {
            best = {{gamma_per_s, rules[r], tau_m, window}, s};
            have = true;
          }
        }
      }
    }
    fits.push_back(best);
  }
  return fits;
}

// The best of the per-window fits; a tie keeps the earlier window (round 1, the paper's, first).
Fit bestOf(const std::vector<Fit>& fits) {
  Fit best = fits.front();
  for (const Fit& f : fits)
    if (f.score.objective > best.score.objective) best = f;
  return best;
}

CalibrationScore evaluateSetting(const std::vector<PedestrianPair>& pairs,
                                 const CalibrationSetting& s, const PathAssessorConfig& base) {
  return scoreOf(evaluateWalkers(pairs, settingConfig(s, base), s.window));
}

std::string fmt(const char* format, double v) {
  if (std::isnan(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string settingText(const CalibrationSetting& s) {
  return "gamma_per_s " + fmt("%.4f", s.gamma_per_s) + ", side_rule " +
         assessment::toString(s.side_rule) + ", tau " + fmt("%.3f", s.tau_m) + " m, window " +
         toString(s.window);
}

std::string scoreText(const CalibrationScore& s) {
  return "ranking " + fmt("%.3f", s.ranking) + ", agreement " + fmt("%.3f", s.agreement) +
         ", objective " + fmt("%.3f", s.objective) + ", auc " + fmt("%.3f", s.auc);
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

const char* toString(WindowKind k) {
  switch (k) {
    case WindowKind::kRound1:
      return "round1";
    case WindowKind::kOnset:
      return "onset";
    case WindowKind::kLead:
      return "lead";
  }
  return "?";
}

std::optional<WindowKind> windowKindFromString(const std::string& name) {
  for (const WindowKind k : {WindowKind::kRound1, WindowKind::kOnset, WindowKind::kLead})
    if (name == toString(k)) return k;
  return std::nullopt;
}

std::string toString(const WindowSetting& w) {
  if (w.kind != WindowKind::kLead) return toString(w.kind);
  return std::string("lead ") + fmt("%g", w.lead_s) + " s";
}

std::optional<AvoidanceOnset> detectAvoidanceOnset(const std::vector<double>& t_s,
                                                   const std::vector<Eigen::Vector2d>& p_m,
                                                   const Eigen::Vector2d& origin_m,
                                                   const Eigen::Vector2d& heading,
                                                   double threshold_m,
                                                   double min_lateral_speed_m_s) {
  const std::size_t n = std::min(t_s.size(), p_m.size());
  std::vector<double> d;
  d.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    d.push_back(cross(heading, p_m[i] - origin_m));
    if (std::abs(d[i]) < threshold_m) continue;
    // Sample i is the first beyond the threshold: walk back while the deviation on its side grew
    // faster than a drift.
    const double s = d[i] > 0.0 ? 1.0 : -1.0;
    std::size_t j = i;
    while (j > 0 && s * (d[j] - d[j - 1]) > min_lateral_speed_m_s * (t_s[j] - t_s[j - 1])) --j;
    return AvoidanceOnset{t_s[j], t_s[i], i};
  }
  return std::nullopt;
}

std::vector<WalkerRun> planWalkerRuns(const std::vector<PedestrianPair>& pairs,
                                      const WindowSetting& window) {
  std::vector<WalkerRun> runs;
  runs.reserve(2 * pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    runs.push_back(planWalkerRun(pairs[i], i, true, window));
    runs.push_back(planWalkerRun(pairs[i], i, false, window));
  }
  return runs;
}

RunOutcome replayRun(const WalkerRun& run, const PathAssessorConfig& config) {
  RunOutcome out;
  if (run.observations.empty()) return out;
  PathRecorder rec(config);
  for (std::size_t i = 0; i < run.observations.size(); ++i) {
    const auto& o = run.observations[i];
    rec.observe(o.t_s, o.human_m, o.robot_m);
    if (i == run.start_after) rec.start(run.walker.window_start_s, run.reference);
  }
  rec.stop(run.stop_t_s);
  const auto snap = rec.snapshot();
  out.cm_m = snap.cm_interaction_m;
  out.samples = snap.interaction_samples;
  out.ca_m = rec.interactionCa();
  return out;
}

PedestrianEvaluation evaluateWalkers(const std::vector<PedestrianPair>& pairs,
                                     const PathAssessorConfig& config,
                                     const WindowSetting& window) {
  PedestrianEvaluation e;
  e.config = config;
  for (auto& r : replayAll(pairs, config, window)) e.walkers.push_back(std::move(r.walker));
  scoreEvaluation(e);
  return e;
}

double gammaPerSample(double gamma_per_s, double sample_period_s) {
  return std::pow(gamma_per_s, sample_period_s);
}

std::vector<WindowSetting> calibrationWindows() {
  std::vector<WindowSetting> w{{WindowKind::kRound1, 0.0}, {WindowKind::kOnset, 0.0}};
  for (const double lead_s : {1.0, 2.0, 3.0, 4.0}) w.push_back({WindowKind::kLead, lead_s});
  return w;
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
  r.paper_setting = {std::pow(0.98, 10), SideRule::kPathSide, 0.4, {}};
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
      const std::vector<Fit> fits = gridSearchPerWindow(fit_pairs, base);
      const Fit fit = bestOf(fits);
      f.setting = fit.setting;
      f.fit = fit.score;
      f.held_out = evaluateSetting(held_pairs, f.setting, base);
      f.paper_held_out = evaluateSetting(held_pairs, r.paper_setting, base);
      for (const Fit& w : fits) {
        f.window_settings.push_back(w.setting);
        f.window_held_out.push_back(evaluateSetting(held_pairs, w.setting, base));
      }
      r.folds.push_back(std::move(f));
    }
  }
  const std::vector<Fit> fits = gridSearchPerWindow(pairs, base);
  const Fit all = bestOf(fits);
  r.final_setting = all.setting;
  r.final_score = all.score;
  // calibrationWindows() starts with round 1: the window the dialogue manager STARTs at.
  r.profile_setting = fits.front().setting;
  r.profile_score = fits.front().score;
  r.paper_score = evaluateSetting(pairs, r.paper_setting, base);
  for (const Fit& w : fits) {
    CalibrationWindowResult wr;
    wr.window = w.setting.window;
    wr.fit = w.setting;
    wr.fit_score = w.score;
    CalibrationSetting paper = r.paper_setting;
    paper.window = wr.window;
    wr.paper = evaluateSetting(pairs, paper, base);
    r.windows.push_back(wr);
  }
  return r;
}

namespace {

std::string padded(std::string s, std::size_t width) {
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}

}  // namespace

std::string formatPedestrianEvaluation(const PedestrianEvaluation& e, double gamma_per_s,
                                       const WindowSetting& window) {
  std::ostringstream o;
  o << "settings: gamma " << fmt("%.6f", e.config.gamma) << " per "
    << fmt("%.3f", e.config.sample_period_s) << " s sample (" << fmt("%.4f", gamma_per_s)
    << " per s), tau " << fmt("%.3f", e.config.tau_m) << " m, side_rule "
    << assessment::toString(e.config.side_rule) << ", window " << toString(window) << "\n";
  std::vector<double> onset_lead_s;  // how long before the closest approach the onsets were
  for (const auto& w : e.walkers)
    if (w.onset_t_s) onset_lead_s.push_back(w.t_cross_s - *w.onset_t_s);
  std::sort(onset_lead_s.begin(), onset_lead_s.end());
  o << "avoidance onsets (|d| >= " << fmt("%.2f", kOnsetThresholdM) << " m, growing faster than "
    << fmt("%.2f", kOnsetMinLateralSpeedMS) << " m/s) of " << onset_lead_s.size()
    << " walkers, before the closest approach by";
  if (onset_lead_s.empty()) {
    o << " -\n";
  } else {
    const auto q = [&](double f) {
      return onset_lead_s[static_cast<std::size_t>(f *
                                                   static_cast<double>(onset_lead_s.size() - 1))];
    };
    o << " " << fmt("%.1f", q(0.25)) << " / " << fmt("%.1f", q(0.5)) << " / "
      << fmt("%.1f", q(0.75)) << " s (quartiles)\n";
  }
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
  o << "RESULT pedestrians_auc " << fmt("%.4f", e.auc) << "\n";
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
  o << "per window (calibrated: the grid's best with that window on all pairs, in-sample; held "
       "out: that window's fit without the sequence, scored on it; paper: gamma 0.98 per "
       "sample, tau 0.4 m, path_side with that window):\n";
  for (std::size_t i = 0; i < r.windows.size(); ++i) {
    const auto& w = r.windows[i];
    o << "  " << padded(toString(w.window), 9) << " calibrated " << scoreText(w.fit_score)
      << " (gamma_per_s " << fmt("%.4f", w.fit.gamma_per_s) << ", "
      << assessment::toString(w.fit.side_rule) << ", tau " << fmt("%.3f", w.fit.tau_m) << ")\n";
    for (const auto& f : r.folds)
      if (i < f.window_held_out.size())
        o << "  " << padded("", 9) << " held out " << f.held_out_ds << " "
          << scoreText(f.window_held_out[i]) << "\n";
    o << "  " << padded("", 9) << " paper      " << scoreText(w.paper) << "\n";
  }
  o << "final fit (all pairs, any window): " << settingText(r.final_setting) << "\n";
  o << "  calibrated " << scoreText(r.final_score) << "\n";
  o << "shipped profile (round-1 window, config/path_assessor_calibrated.yaml): "
    << settingText(r.profile_setting) << "\n";
  o << "  calibrated " << scoreText(r.profile_score) << "\n";
  o << "  paper      " << scoreText(r.paper_score) << " (" << settingText(r.paper_setting) << ")\n";
  o << "RESULT pedestrians_calibrated_gamma_per_s " << fmt("%.4f", r.profile_setting.gamma_per_s)
    << "\n";
  o << "RESULT pedestrians_calibrated_side_rule "
    << assessment::toString(r.profile_setting.side_rule) << "\n";
  o << "RESULT pedestrians_calibrated_tau_m " << fmt("%.3f", r.profile_setting.tau_m) << "\n";
  const WindowSetting& best = r.final_setting.window;
  o << "RESULT pedestrians_best_window "
    << (best.kind == WindowKind::kLead ? "lead_" + fmt("%g", best.lead_s) + "s"
                                       : std::string(toString(best.kind)))
    << "\n";
  o << "RESULT pedestrians_best_window_objective " << fmt("%.4f", r.final_score.objective) << "\n";
  o << "RESULT pedestrians_round1_objective " << fmt("%.4f", r.profile_score.objective) << "\n";
  return o.str();
}

}  // namespace coopnav::ctl
