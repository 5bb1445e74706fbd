#include "pedestrians_forecast.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>

#include "../population/stats.hpp"

namespace coopnav::ctl {
namespace {

using assessment::ForecastFeatures;
using assessment::ForecastModel;
using assessment::ForecastObservation;
using assessment::kForecastFeatureCount;
using assessment::PathAssessorConfig;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTimeTolS = 1e-6;
// Score of an unknown judgement: below any CM or probability.
constexpr double kUnknownScore = -1e9;

std::string fmt(const char* format, double v) {
  if (std::isnan(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

bool truthOf(const WalkerResult& w) { return w.dev_away_m >= kStepAwayTruthM; }

// AUC and accuracy of judgements over the walkers `idx`.
std::pair<double, double> aucAccuracy(const std::vector<Judgement>& j,
                                      const std::vector<WalkerRun>& runs,
                                      const std::vector<std::size_t>& idx) {
  std::vector<double> pos;
  std::vector<double> neg;
  std::size_t right = 0;
  for (const std::size_t i : idx) {
    const bool truth = truthOf(runs[i].walker);
    (truth ? pos : neg).push_back(j[i].score);
    if (j[i].said == truth) ++right;
  }
  const double acc =
      idx.empty() ? kNaN : static_cast<double>(right) / static_cast<double>(idx.size());
  return {population::mannWhitneyAuc(pos, neg), acc};
}

double percentile(std::vector<double> v, double q) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

// One row: walkers of the pairs in `pair_groups` (each group: the pairs of one sequence,
// resampled within it, so the pooled row keeps each sequence's size).
DecisionScore scoreRow(const std::string& ds, double lead_s, const std::vector<Judgement>& j,
                       const std::vector<WalkerRun>& runs,
                       const std::vector<std::vector<std::size_t>>& pair_groups) {
  DecisionScore s;
  s.ds = ds;
  s.lead_s = lead_s;
  std::vector<std::size_t> idx;
  for (const auto& g : pair_groups)
    for (const std::size_t p : g) {
      idx.push_back(2 * p);
      idx.push_back(2 * p + 1);
    }
  s.walkers = idx.size();
  for (const std::size_t i : idx) {
    if (j[i].known) ++s.known;
    if (truthOf(runs[i].walker)) ++s.positives;
  }
  std::tie(s.auc, s.accuracy) = aucAccuracy(j, runs, idx);
  std::mt19937_64 rng(kBootstrapSeed);
  std::vector<double> aucs;
  std::vector<double> accs;
  std::vector<std::size_t> boot;
  for (int b = 0; b < kBootstrapResamples; ++b) {
    boot.clear();
    for (const auto& g : pair_groups) {
      std::uniform_int_distribution<std::size_t> pick(0, g.size() - 1);
      for (std::size_t k = 0; k < g.size(); ++k) {
        const std::size_t p = g[pick(rng)];
        boot.push_back(2 * p);
        boot.push_back(2 * p + 1);
      }
    }
    const auto [auc, acc] = aucAccuracy(j, runs, boot);
    aucs.push_back(auc);
    accs.push_back(acc);
  }
  const double a = 0.5 * (1.0 - kBootstrapLevel);
  s.auc_lo = percentile(aucs, a);
  s.auc_hi = percentile(aucs, 1.0 - a);
  s.accuracy_lo = percentile(accs, a);
  s.accuracy_hi = percentile(accs, 1.0 - a);
  return s;
}

std::vector<std::string> sequencesOf(const std::vector<PedestrianPair>& pairs) {
  std::vector<std::string> seqs;
  for (const auto& p : pairs)
    if (std::find(seqs.begin(), seqs.end(), p.ds) == seqs.end()) seqs.push_back(p.ds);
  return seqs;
}

Eigen::Vector2d headingOf(const WalkerRun& run) {
  return (run.reference.back() - run.reference.front()).normalized();
}

double runDecisionTime(const WalkerRun& run, double lead_s) {
  return run.walker.t_cross_s - lead_s;
}

std::vector<PedestrianPair> pairsWhere(const std::vector<PedestrianPair>& pairs,
                                       const std::string& ds, bool equal) {
  std::vector<PedestrianPair> out;
  for (const auto& p : pairs)
    if ((p.ds == ds) == equal) out.push_back(p);
  return out;
}

}  // namespace

const std::vector<double>& decisionLeadsS() {
  static const std::vector<double> leads{4.0, 3.0, 2.0, 1.0, 0.0};
  return leads;
}

std::vector<std::vector<Judgement>> cmJudgements(const std::vector<PedestrianPair>& pairs,
                                                 const PathAssessorConfig& config) {
  const auto runs = planWalkerRuns(pairs);
  std::vector<std::vector<Judgement>> out;
  for (const double lead_s : decisionLeadsS()) {
    std::vector<Judgement> js;
    for (const auto& run : runs) {
      const double t_s = runDecisionTime(run, lead_s);
      assessment::PathRecorder rec(config);
      bool started = false;
      for (std::size_t i = 0; i < run.observations.size(); ++i) {
        const auto& o = run.observations[i];
        if (o.t_s > t_s + kTimeTolS) break;
        rec.observe(o.t_s, o.human_m, o.robot_m);
        if (i == run.start_after) started = rec.start(run.walker.window_start_s, run.reference);
      }
      Judgement j;
      const auto snap = rec.snapshot();
      if (started && snap.cm_window_m) {
        j.known = true;
        j.score = *snap.cm_window_m;
        j.said = snap.is_contributing_window == Tristate::kTrue;
      } else {
        j.score = kUnknownScore;
      }
      js.push_back(j);
    }
    out.push_back(std::move(js));
  }
  return out;
}

std::optional<ForecastFeatures> runFeaturesAt(const WalkerRun& run, double t_s) {
  std::vector<ForecastObservation> obs;
  for (const auto& o : run.observations) {
    if (o.t_s > t_s + kTimeTolS) break;
    obs.push_back({o.t_s, o.human_m, o.robot_m});
  }
  if (obs.empty()) return std::nullopt;
  return assessment::forecastFeatures(obs, run.reference.front(), headingOf(run));
}

ForecastModel fitForecast(const std::vector<PedestrianPair>& pairs) {
  std::vector<ForecastFeatures> xs;
  std::vector<int> ys;
  for (const auto& run : planWalkerRuns(pairs)) {
    const int y = truthOf(run.walker) ? 1 : 0;
    for (const auto& o : run.observations) {
      if (run.walker.t_cross_s - o.t_s > kForecastFitHorizonS + kTimeTolS) continue;
      const auto f = runFeaturesAt(run, o.t_s);
      if (!f) continue;
      xs.push_back(*f);
      ys.push_back(y);
    }
  }
  return assessment::fitForecastModel(xs, ys, kForecastL2);
}

namespace {

std::vector<Judgement> forecastJudgementsAt(const ForecastModel& m,
                                            const std::vector<WalkerRun>& runs, double lead_s) {
  // Through assessment::CooperationForecaster: what a daemon would publish at that time.
  std::vector<Judgement> js;
  for (const auto& run : runs) {
    assessment::CooperationForecaster fc(m);
    fc.start(run.reference.front(), headingOf(run));
    const double t_s = runDecisionTime(run, lead_s);
    for (const auto& o : run.observations) {
      if (o.t_s > t_s + kTimeTolS) break;
      fc.observe(o.t_s, o.human_m, o.robot_m);
    }
    Judgement j;
    if (!std::isnan(fc.pContributing())) {
      j.known = true;
      j.score = fc.pContributing();
      j.said = j.score > kForecastThreshold;
    } else {
      j.score = kUnknownScore;
    }
    js.push_back(j);
  }
  return js;
}

}  // namespace

DecisionTable scoreJudgements(const std::string& judge, const std::string& note,
                              const std::vector<PedestrianPair>& pairs,
                              const std::vector<std::vector<Judgement>>& judgements) {
  DecisionTable t;
  t.judge = judge;
  t.note = note;
  const auto runs = planWalkerRuns(pairs);
  std::vector<std::vector<std::size_t>> groups;
  const auto seqs = sequencesOf(pairs);
  for (const auto& ds : seqs) {
    std::vector<std::size_t> g;
    for (std::size_t p = 0; p < pairs.size(); ++p)
      if (pairs[p].ds == ds) g.push_back(p);
    groups.push_back(g);
  }
  const auto& leads = decisionLeadsS();
  for (std::size_t l = 0; l < leads.size() && l < judgements.size(); ++l) {
    for (std::size_t g = 0; g < groups.size(); ++g)
      t.rows.push_back(scoreRow(seqs[g], leads[l], judgements[l], runs, {groups[g]}));
    t.rows.push_back(scoreRow("all", leads[l], judgements[l], runs, groups));
  }
  return t;
}

ForecastStudy runForecastStudy(const std::vector<PedestrianPair>& pairs,
                               const CalibrationResult& cal) {
  const CalibrationSetting& calibrated_profile = cal.profile_setting;
  ForecastStudy s;
  const auto runs = planWalkerRuns(pairs);
  const auto seqs = sequencesOf(pairs);
  const auto& leads = decisionLeadsS();

  const PathAssessorConfig paper{};
  s.tables.push_back(scoreJudgements("paper CM", "gamma 0.98 per 0.1 s, tau 0.4 m, path_side",
                                     pairs, cmJudgements(pairs, paper)));

  // Calibrated, leave-one-sequence-out: the round-1 grid fit without the sequence, judged on it.
  std::vector<std::vector<Judgement>> cal_loso(leads.size(), std::vector<Judgement>(runs.size()));
  std::vector<std::vector<Judgement>> fc_loso(leads.size(), std::vector<Judgement>(runs.size()));
  std::string cal_note;
  for (const auto& ds : seqs) {
    const auto fit_pairs = pairsWhere(pairs, ds, false);
    if (fit_pairs.empty()) continue;
    // calibrationWindows() starts with round 1: window_settings[0] is the round-1 fit.
    const auto fold = std::find_if(cal.folds.begin(), cal.folds.end(),
                                   [&](const CalibrationFold& f) { return f.held_out_ds == ds; });
    if (fold == cal.folds.end() || fold->window_settings.empty())
      throw std::invalid_argument("runForecastStudy: no calibration fold holds out " + ds);
    const CalibrationSetting cs = fold->window_settings.front();
    cal_note += (cal_note.empty() ? "" : "; ") + std::string("held out ") + ds + ": gamma_per_s " +
                fmt("%.4f", cs.gamma_per_s) + ", " + assessment::toString(cs.side_rule) + ", tau " +
                fmt("%.3f", cs.tau_m);
    const auto cj = cmJudgements(pairs, settingConfig(cs));
    const ForecastModel m = fitForecast(fit_pairs);
    s.fold_models.emplace_back(ds, m);
    for (std::size_t l = 0; l < leads.size(); ++l) {
      const auto fj = forecastJudgementsAt(m, runs, leads[l]);
      for (std::size_t i = 0; i < runs.size(); ++i)
        if (runs[i].walker.ds == ds) {
          cal_loso[l][i] = cj[l][i];
          fc_loso[l][i] = fj[i];
        }
    }
  }
  s.tables.push_back(scoreJudgements("calibrated CM, LOSO", cal_note, pairs, cal_loso));
  s.tables.push_back(scoreJudgements("calibrated CM, shipped profile (in-sample)",
                                     "gamma_per_s " + fmt("%.4f", calibrated_profile.gamma_per_s) +
                                         ", " + assessment::toString(calibrated_profile.side_rule) +
                                         ", tau " + fmt("%.3f", calibrated_profile.tau_m),
                                     pairs,
                                     cmJudgements(pairs, settingConfig(calibrated_profile))));
  s.tables.push_back(scoreJudgements("forecast p_contributing, LOSO",
                                     "logistic, l2 " + fmt("%g", kForecastL2) +
                                         ", fitted on the other sequence's walkers at "
                                         "every annotated time within " +
                                         fmt("%g", kForecastFitHorizonS) + " s of the crossing",
                                     pairs, fc_loso));
  s.model = fitForecast(pairs);
  std::vector<std::vector<Judgement>> fc_in;
  fc_in.reserve(leads.size());
  for (const double lead_s : leads) fc_in.push_back(forecastJudgementsAt(s.model, runs, lead_s));
  s.tables.push_back(scoreJudgements("forecast p_contributing, fit on all (in-sample ceiling)",
                                     "the shipped forecast profile", pairs, fc_in));

  // What the held-out forecast misses at 2 s, per sequence.
  std::ostringstream o;
  const auto l2 =
      static_cast<std::size_t>(std::find(leads.begin(), leads.end(), 2.0) - leads.begin());
  for (const auto& ds : seqs) {
    std::size_t fn = 0, fp = 0, fn_amb = 0, fp_amb = 0, amb = 0, unknown = 0, n = 0;
    std::vector<double> fn_dev;
    for (std::size_t i = 0; i < runs.size(); ++i) {
      if (runs[i].walker.ds != ds) continue;
      ++n;
      const auto f = runFeaturesAt(runs[i], runDecisionTime(runs[i], 2.0));
      const bool ambiguous = f && f->side_ambiguous;
      if (ambiguous) ++amb;
      const Judgement& j = fc_loso[l2][i];
      if (!j.known) ++unknown;
      const bool truth = truthOf(runs[i].walker);
      if (truth && !j.said) {
        ++fn;
        fn_amb += ambiguous ? 1 : 0;
        if (runs[i].walker.onset_t_s)
          fn_dev.push_back(runs[i].walker.t_cross_s - *runs[i].walker.onset_t_s);
      }
      if (!truth && j.said) {
        ++fp;
        fp_amb += ambiguous ? 1 : 0;
      }
    }
    o << "  " << ds << ": " << n << " walkers, " << amb << " with the robot's side ambiguous at "
      << "2 s (in line within " << fmt("%.2f", assessment::kForecastInLineM) << " m), " << unknown
      << " unknown; missed cooperation (FN) " << fn << " (" << fn_amb << " ambiguous; their onsets "
      << fmt("%.1f", population::median(fn_dev))
      << " s before the crossing, median), false cooperation (FP) " << fp << " (" << fp_amb
      << " ambiguous)\n";
  }
  s.misses = o.str();
  for (const auto& ds : seqs) {
    const auto fold = std::find_if(cal.folds.begin(), cal.folds.end(),
                                   [&](const CalibrationFold& f) { return f.held_out_ds == ds; });
    if (fold == cal.folds.end() || fold->window_settings.empty()) continue;
    s.end_of_interaction.push_back(
        endOfInteraction(pairsWhere(pairs, ds, true), ds, fold->window_settings.front()));
  }
  return s;
}

// Two walkers nearly in line at t0: the side each is on of the other is noise, and so is the
// sign of CA until one steps off (the side rule's deadband and memory, path_assessment.hpp).
EndOfInteractionFold endOfInteraction(const std::vector<PedestrianPair>& pairs,
                                      const std::string& ds, const CalibrationSetting& setting) {
  EndOfInteractionFold f;
  f.ds = ds;
  f.pairs = pairs.size();
  PedestrianEvaluation e = evaluateWalkers(pairs, settingConfig(setting), setting.window);
  scoreEvaluation(e);
  f.ranking = e.ranking;
  f.agreement = e.agreement;
  const double tau_m = setting.tau_m;
  for (std::size_t p = 0; p < pairs.size() && 2 * p + 1 < e.walkers.size(); ++p) {
    const PedestrianPair& pair = pairs[p];
    const auto at = [](const PedestrianTrack& tr, double t_s) {
      std::size_t i = 0;
      while (i + 1 < tr.t_s.size() && tr.t_s[i + 1] <= t_s) ++i;
      if (i + 1 >= tr.t_s.size() || tr.t_s[i] >= t_s) return Eigen::Vector2d(tr.x_m[i], tr.y_m[i]);
      const double w = (t_s - tr.t_s[i]) / (tr.t_s[i + 1] - tr.t_s[i]);
      return Eigen::Vector2d(tr.x_m[i] + w * (tr.x_m[i + 1] - tr.x_m[i]),
                             tr.y_m[i] + w * (tr.y_m[i + 1] - tr.y_m[i]));
    };
    const Eigen::Vector2d pa = at(pair.a, pair.t0_s), pb = at(pair.b, pair.t0_s);
    const Eigen::Vector2d ua(pair.heading_a[0], pair.heading_a[1]);
    const Eigen::Vector2d ub(pair.heading_b[0], pair.heading_b[1]);
    const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& d) {
      return u.x() * d.y() - u.y() * d.x();
    };
    // The lateral gap as each walker sees it; in line when either is within the threshold.
    const double gap_m = std::min(std::abs(cross(ua, pb - pa)), std::abs(cross(ub, pa - pb)));
    const bool in_line = gap_m < assessment::kForecastInLineM;
    f.pairs_in_line += in_line ? 1 : 0;
    const WalkerResult& a = e.walkers[2 * p];
    const WalkerResult& b = e.walkers[2 * p + 1];
    const std::string where = "pair " + std::to_string(p) + " (ids " + std::to_string(a.id) + "/" +
                              std::to_string(b.id) + ", gap at t0 " + fmt("%.2f", gap_m) + " m" +
                              (in_line ? ", in line" : "") + ")";
    if (a.cm_m && b.cm_m && std::abs(a.dev_away_m - b.dev_away_m) >= kRankingMinDifferenceM) {
      const bool right = a.dev_away_m > b.dev_away_m ? *a.cm_m > *b.cm_m : *b.cm_m > *a.cm_m;
      ++f.ranked;
      f.ranked_right += right ? 1 : 0;
      f.ranked_in_line += in_line ? 1 : 0;
      f.ranked_right_in_line += in_line && right ? 1 : 0;
      if (!right)
        f.misses.push_back("ranking: " + where + ": dev_away " + fmt("%.2f", a.dev_away_m) + " / " +
                           fmt("%.2f", b.dev_away_m) + " m, CM " + fmt("%.2f", *a.cm_m) + " / " +
                           fmt("%.2f", *b.cm_m) + " m");
    }
    for (const WalkerResult* w : {&a, &b}) {
      if (!w->cm_m) continue;
      const bool said = *w->cm_m > tau_m, truth = w->dev_away_m >= kStepAwayTruthM;
      ++f.judged;
      f.agreeing += said == truth ? 1 : 0;
      f.judged_in_line += in_line ? 1 : 0;
      f.agreeing_in_line += in_line && said == truth ? 1 : 0;
      if (said != truth)
        f.misses.push_back(std::string(said ? "agreement FP: " : "agreement FN: ") + where +
                           ": walker " + std::to_string(w->id) + " dev_away " +
                           fmt("%.2f", w->dev_away_m) + " m, CM " + fmt("%.2f", *w->cm_m) +
                           " m against tau " + fmt("%.3f", tau_m) + " m");
    }
  }
  return f;
}

std::string formatDecisionTables(const std::vector<DecisionTable>& tables) {
  std::ostringstream o;
  for (const auto& t : tables) {
    o << t.judge << " (" << t.note << ")\n";
    o << "  lead  sequence          walkers known pos  AUC [95% CI]            accuracy [95% CI]\n";
    for (const auto& r : t.rows) {
      char buf[256];
      std::snprintf(buf, sizeof buf, "  %3.0f s %-17s %7zu %5zu %4zu %s [%s, %s]   %s [%s, %s]\n",
                    r.lead_s, r.ds.c_str(), r.walkers, r.known, r.positives,
                    fmt("%.3f", r.auc).c_str(), fmt("%.3f", r.auc_lo).c_str(),
                    fmt("%.3f", r.auc_hi).c_str(), fmt("%.3f", r.accuracy).c_str(),
                    fmt("%.3f", r.accuracy_lo).c_str(), fmt("%.3f", r.accuracy_hi).c_str());
      o << buf;
    }
  }
  return o.str();
}

std::string formatForecastStudy(const ForecastStudy& s) {
  std::ostringstream o;
  o << "judgement at t_cross - lead: will the walker have stepped >= "
    << fmt("%.2f", kStepAwayTruthM) << " m away by the crossing? (AUC: Mann-Whitney, unknown "
    << "judgements tied at the bottom; accuracy: unknown = not contributing; CI: "
    << kBootstrapResamples << " bootstrap resamples of the pairs within each sequence, seed "
    << kBootstrapSeed << ")\n";
  o << formatDecisionTables(s.tables);
  o << "forecast misses at 2 s (LOSO):\n" << s.misses;
  o << "end-of-interaction judgement held out (calibrated CM, round-1 fit on the other sequence, "
       "read at the crossing; in line: the other within "
    << fmt("%.2f", assessment::kForecastInLineM)
    << " m of the walker's line at t0, the sign of CA ambiguous until one steps off):\n";
  const auto share = [](std::size_t k, std::size_t n) {
    return n == 0 ? std::string("-")
                  : std::to_string(k) + "/" + std::to_string(n) + " = " +
                        fmt("%.3f", static_cast<double>(k) / static_cast<double>(n));
  };
  for (const auto& f : s.end_of_interaction) {
    o << "  " << f.ds << " (" << f.pairs << " pairs, " << f.pairs_in_line << " in line): ranking "
      << share(f.ranked_right, f.ranked) << " (in line "
      << share(f.ranked_right_in_line, f.ranked_in_line) << "), agreement "
      << share(f.agreeing, f.judged) << " (in line " << share(f.agreeing_in_line, f.judged_in_line)
      << "); both >= 0.9: " << (f.ranking >= 0.9 && f.agreement >= 0.9 ? "yes" : "NO") << "\n";
    for (const auto& m : f.misses) o << "    " << m << "\n";
  }
  const auto& names = assessment::forecastFeatureNames();
  o << "forecast coefficients (standardised features):\n";
  const auto row = [&](const std::string& label, const ForecastModel& m) {
    o << "  " << label << ": bias " << fmt("%+.3f", m.bias);
    for (std::size_t i = 0; i < kForecastFeatureCount; ++i)
      o << ", " << names[i] << " " << fmt("%+.3f", m.weight[i]);
    o << "\n";
  };
  for (const auto& [ds, m] : s.fold_models) row("without " + ds, m);
  row("all pairs (profile)", s.model);
  for (const auto& f : s.end_of_interaction) {
    o << "RESULT pedestrians_end_ranking_" << f.ds << " " << fmt("%.4f", f.ranking) << "\n";
    o << "RESULT pedestrians_end_agreement_" << f.ds << " " << fmt("%.4f", f.agreement) << "\n";
  }
  for (const auto& t : s.tables) {
    std::string key;
    if (t.judge.rfind("paper", 0) == 0) key = "paper_cm";
    if (t.judge == "calibrated CM, LOSO") key = "calibrated_cm_loso";
    if (t.judge == "forecast p_contributing, LOSO") key = "forecast_loso";
    if (key.empty()) continue;
    for (const auto& r : t.rows)
      if (r.ds == "all")
        o << "RESULT pedestrians_" << key << "_auc_lead_" << fmt("%.0f", r.lead_s) << "s "
          << fmt("%.4f", r.auc) << "\n";
  }
  return o.str();
}

}  // namespace coopnav::ctl
