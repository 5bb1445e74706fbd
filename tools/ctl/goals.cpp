#include "goals.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <set>

#include "../population/stats.hpp"
#include "coopnav/planning/goal_inference.hpp"

namespace coopnav::ctl {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMinProbability = 1e-12;  ///< floor of p_true in the log score
constexpr double kTimeEps_s = 1e-9;
/// [m] closer than this to its exit, a walker has no direction to it worth measuring (a goal this
/// close counts as reached in GoalBelief).
constexpr double kAtExit_m = 0.5;
constexpr double kTurnDeg = 30.0;  ///< exit further off the heading at t: the walker turns
constexpr double kSharpTurnDeg = 45.0;
constexpr double kDetourRatio = 1.2;  ///< remaining path / straight distance above: a detour

struct Cluster {
  std::vector<Eigen::Vector2d> members;
  Eigen::Vector2d centre{0.0, 0.0};
};

Eigen::Vector2d exitOf(const PedestrianTrack& t) { return {t.x_m.back(), t.y_m.back()}; }

std::vector<Cluster> clusterExits(const std::vector<Eigen::Vector2d>& exits, double radius_m,
                                  ExitClustering how) {
  std::vector<Cluster> out;
  if (how == ExitClustering::kGreedyRadius) {
    for (const auto& e : exits) {
      auto it = std::find_if(out.begin(), out.end(), [&](const Cluster& c) {
        return (c.members.front() - e).norm() <= radius_m;
      });
      if (it == out.end()) {
        out.push_back({{e}, e});
      } else {
        it->members.push_back(e);
      }
    }
  } else {
    // Union-find, each exit linked to every earlier one within the radius.
    std::vector<std::size_t> parent(exits.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto root = [&](std::size_t i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    for (std::size_t i = 0; i < exits.size(); ++i) {
      for (std::size_t j = 0; j < i; ++j) {
        if ((exits[i] - exits[j]).norm() <= radius_m) parent[root(i)] = root(j);
      }
    }
    // Clusters in order of their first exit.
    std::vector<std::size_t> slot(exits.size(), exits.size());
    for (std::size_t i = 0; i < exits.size(); ++i) {
      const std::size_t r = root(i);
      if (slot[r] == exits.size()) {
        slot[r] = out.size();
        out.emplace_back();
      }
      out[slot[r]].members.push_back(exits[i]);
    }
  }
  for (auto& c : out) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (const auto& m : c.members) sum += m;
    c.centre = sum / static_cast<double>(c.members.size());
  }
  return out;
}

/// The cluster a walker's exit belongs to (the rule of the clustering), -1 for none.
int truthCluster(const std::vector<Cluster>& clusters, const Eigen::Vector2d& exit, double radius_m,
                 ExitClustering how) {
  if (how == ExitClustering::kGreedyRadius) {
    for (std::size_t k = 0; k < clusters.size(); ++k) {
      if ((clusters[k].members.front() - exit).norm() <= radius_m) return static_cast<int>(k);
    }
    return -1;
  }
  int best = -1;
  double best_m = radius_m;
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    for (const auto& m : clusters[k].members) {
      const double d = (m - exit).norm();
      if (d <= best_m && (best < 0 || d < best_m)) {
        best = static_cast<int>(k);
        best_m = d;
      }
    }
  }
  return best;
}

double ratio(std::size_t num, std::size_t den) {
  return den == 0 ? kNaN : static_cast<double>(num) / static_cast<double>(den);
}

std::vector<std::string> sequences(const std::vector<PedestrianPair>& pairs) {
  std::vector<std::string> out;
  for (const auto& p : pairs) {
    if (std::find(out.begin(), out.end(), p.ds) == out.end()) out.push_back(p.ds);
  }
  return out;
}

/// All pairs but those of sequence ds.
std::vector<PedestrianPair> without(const std::vector<PedestrianPair>& pairs,
                                    const std::string& ds) {
  std::vector<PedestrianPair> out;
  for (const auto& p : pairs) {
    if (p.ds != ds) out.push_back(p);
  }
  return out;
}

struct FitResult {
  double beta_per_m{0.0};
  double heading_kappa{0.0};
};

/// Max mean ln P(true goal) over the grids (β fixed when given; κ only with the heading term).
FitResult fitParams(const std::vector<PedestrianPair>& pairs, GoalEvalOptions o,
                    std::optional<double> beta_per_m) {
  const std::vector<double> betas = beta_per_m ? std::vector<double>{*beta_per_m} : goalBetasPerM();
  const std::vector<double> kappas =
      o.heading_term ? goalHeadingKappas() : std::vector<double>{o.heading_kappa};
  FitResult best{betas.front(), kappas.front()};
  double best_score = -std::numeric_limits<double>::infinity();
  for (const double kappa : kappas) {
    for (const double beta : betas) {
      o.beta_per_m = beta;
      o.heading_kappa = kappa;
      const double score = evaluateGoalInference(pairs, o).mean_log_p_true;
      if (score > best_score) {
        best_score = score;
        best = {beta, kappa};
      }
    }
  }
  return best;
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

std::string configName(const GoalEvalOptions& o) {
  return std::string(toString(o.clustering)) +
         (o.frequency_prior ? " + exit-frequency prior" : " + uniform prior") +
         (o.heading_term ? " + heading" : "");
}

std::string count(std::size_t num, std::size_t den) {
  return fmt("%.3f", ratio(num, den)) + " (" + std::to_string(num) + "/" + std::to_string(den) +
         ")";
}

}  // namespace

const char* toString(ExitClustering c) {
  return c == ExitClustering::kGreedyRadius ? "greedy radius" : "chained";
}

GoalEvaluation evaluateGoalInference(const std::vector<PedestrianPair>& pairs,
                                     const GoalEvalOptions& options, const std::string& only_ds) {
  GoalEvaluation e;
  e.options = options;
  GoalInferenceOptions gi;
  gi.beta_per_m = options.beta_per_m;
  double log_sum = 0.0;
  for (std::size_t pi = 0; pi < pairs.size(); ++pi) {
    const PedestrianPair& pair = pairs[pi];
    if (!only_ds.empty() && pair.ds != only_ds) continue;
    // Exits of every other walker of the sequence, once per track id, in file order.
    std::vector<Eigen::Vector2d> exits;
    std::set<long> seen{pair.a.id, pair.b.id};
    for (const auto& other : pairs) {
      if (other.ds != pair.ds) continue;
      for (const PedestrianTrack* t : {&other.a, &other.b}) {
        if (seen.insert(t->id).second) exits.push_back(exitOf(*t));
      }
    }
    const auto clusters = clusterExits(exits, options.cluster_radius_m, options.clustering);
    std::vector<Eigen::Vector2d> goals;
    std::vector<double> prior;
    for (const auto& c : clusters) {
      goals.push_back(c.centre);
      prior.push_back(options.frequency_prior ? static_cast<double>(c.members.size()) : 1.0);
    }
    const auto distances = std::make_shared<GoalDistances>(nullptr, goals, gi);
    for (const PedestrianTrack* t : {&pair.a, &pair.b}) {
      GoalCase gc;
      gc.pair_index = pi;
      gc.ds = pair.ds;
      gc.id = t->id;
      gc.candidates = clusters.size();
      const int truth =
          truthCluster(clusters, exitOf(*t), options.cluster_radius_m, options.clustering);
      gc.has_candidate = truth >= 0;
      GoalBelief belief(distances, prior);
      const double until_s = pair.t_cross_s - options.lead_s + kTimeEps_s;
      std::size_t seen_n = 0;  // samples up to t
      for (; seen_n < t->t_s.size() && t->t_s[seen_n] <= until_s; ++seen_n) {
        if (belief.observe(t->t_s[seen_n], {t->x_m[seen_n], t->y_m[seen_n]})) ++gc.observations;
      }
      std::vector<double> posterior = belief.probabilities();
      int pick = belief.mostLikely();
      if (seen_n > 0) {
        const std::size_t last = seen_n - 1;
        const Eigen::Vector2d q(t->x_m[last], t->y_m[last]);
        std::size_t first = last;
        while (first > 0 &&
               t->t_s[first - 1] >= t->t_s[last] - options.heading_window_s - kTimeEps_s) {
          --first;
        }
        const Eigen::Vector2d heading = q - Eigen::Vector2d(t->x_m[first], t->y_m[first]);
        gc.has_heading = heading.norm() >= options.min_heading_step_m;
        const Eigen::Vector2d to_exit = exitOf(*t) - q;
        if (to_exit.norm() >= kAtExit_m) {
          double rest_m = 0.0;
          for (std::size_t k = last; k + 1 < t->t_s.size(); ++k) {
            rest_m += std::hypot(t->x_m[k + 1] - t->x_m[k], t->y_m[k + 1] - t->y_m[k]);
          }
          gc.remaining_path_ratio = rest_m / to_exit.norm();
          if (gc.has_heading) {
            const double c = heading.dot(to_exit) / (heading.norm() * to_exit.norm());
            gc.exit_off_heading_deg = std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
          }
        }
        if (gc.has_heading) {
          double best_cos = -std::numeric_limits<double>::infinity();
          for (std::size_t k = 0; k < clusters.size(); ++k) {
            for (const auto& m : clusters[k].members) {
              const Eigen::Vector2d to = m - q;
              if (!(to.norm() > 0.0)) continue;
              const double c = heading.dot(to) / (heading.norm() * to.norm());
              if (c > best_cos) {
                best_cos = c;
                gc.heading_pick = static_cast<int>(k);
              }
            }
          }
          gc.heading_correct = gc.heading_pick >= 0 && gc.heading_pick == truth;
        }
        if (options.heading_term && gc.has_heading && !posterior.empty()) {
          double sum = 0.0;
          for (std::size_t k = 0; k < clusters.size(); ++k) {
            posterior[k] *=
                headingLikelihood(heading, q, clusters[k].members, options.heading_kappa);
            sum += posterior[k];
          }
          if (sum > 0.0) {
            pick = 0;
            for (std::size_t k = 0; k < posterior.size(); ++k) {
              posterior[k] /= sum;
              if (posterior[k] > posterior[static_cast<std::size_t>(pick)]) {
                pick = static_cast<int>(k);
              }
            }
          } else {
            posterior = belief.probabilities();  // underflow everywhere: the term says nothing
          }
        }
      }
      if (gc.has_candidate) {
        gc.p_true = posterior[static_cast<std::size_t>(truth)];
        gc.correct = pick == truth;
        log_sum += std::log(std::max(gc.p_true, kMinProbability));
      }
      ++e.walkers;
      e.with_candidate += gc.has_candidate ? 1 : 0;
      e.correct += gc.correct ? 1 : 0;
      e.cases.push_back(gc);
    }
  }
  e.accuracy_all = ratio(e.correct, e.walkers);
  e.accuracy_with_candidate = ratio(e.correct, e.with_candidate);
  e.mean_log_p_true =
      e.with_candidate == 0 ? kNaN : log_sum / static_cast<double>(e.with_candidate);
  return e;
}

std::vector<double> goalBetasPerM() { return {0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0, 5.0}; }

std::vector<double> goalHeadingKappas() { return {0.0, 0.5, 1.0, 2.0, 3.0, 5.0, 8.0, 12.0, 20.0}; }

double headingLikelihood(const Eigen::Vector2d& heading, const Eigen::Vector2d& position_m,
                         const std::vector<Eigen::Vector2d>& members_m, double kappa) {
  double sum = 0.0;
  std::size_t used = 0;
  for (const auto& m : members_m) {
    const Eigen::Vector2d to = m - position_m;
    const double d = to.norm();
    if (!(d > 0.0)) continue;
    // exp(κ (cos θ − 1)) rather than exp(κ cos θ): the same ratios between goals (the von Mises
    // normaliser I0(κ) is common to all), no overflow.
    sum += std::exp(kappa * (heading.dot(to) / (heading.norm() * d) - 1.0));
    ++used;
  }
  return used == 0 ? 1.0 : sum / static_cast<double>(used);
}

namespace {

GoalConfigResult evaluateConfig(const std::vector<PedestrianPair>& pairs,
                                std::optional<double> beta_per_m, const GoalEvalOptions& options) {
  GoalConfigResult c;
  c.options = options;
  for (const auto& ds : sequences(pairs)) {
    GoalFold f;
    f.held_out_ds = ds;
    GoalEvalOptions o = c.options;
    const FitResult fit = fitParams(without(pairs, ds), o, beta_per_m);
    o.beta_per_m = fit.beta_per_m;
    o.heading_kappa = fit.heading_kappa;
    f.beta_per_m = fit.beta_per_m;
    f.heading_kappa = fit.heading_kappa;
    f.held_out = evaluateGoalInference(pairs, o, ds);
    c.walkers += f.held_out.walkers;
    c.with_candidate += f.held_out.with_candidate;
    c.correct += f.held_out.correct;
    c.folds.push_back(std::move(f));
  }
  c.accuracy_all = ratio(c.correct, c.walkers);
  c.accuracy_with_candidate = ratio(c.correct, c.with_candidate);
  const FitResult fit = fitParams(pairs, c.options, beta_per_m);
  c.options.beta_per_m = fit.beta_per_m;
  c.options.heading_kappa = fit.heading_kappa;
  for (const double beta : goalBetasPerM()) {
    GoalEvalOptions o = c.options;
    o.beta_per_m = beta;
    c.sweep.push_back(evaluateGoalInference(pairs, o));
  }
  if (c.options.heading_term) {
    for (const double kappa : goalHeadingKappas()) {
      GoalEvalOptions o = c.options;
      o.heading_kappa = kappa;
      c.kappa_sweep.push_back(evaluateGoalInference(pairs, o));
    }
  }
  return c;
}

/// The held-out cases of a configuration, pooled over its folds (the same walkers, in the same
/// order, for every configuration).
std::vector<GoalCase> heldOutCases(const GoalConfigResult& c) {
  std::vector<GoalCase> out;
  for (const auto& f : c.folds)
    out.insert(out.end(), f.held_out.cases.begin(), f.held_out.cases.end());
  return out;
}

GoalCeilingRow ceilingRow(const std::string& name, const std::vector<GoalCase>& path,
                          const std::vector<GoalCase>& combined,
                          const std::function<bool(const GoalCase&)>& in) {
  GoalCeilingRow row;
  row.name = name;
  std::vector<double> off_deg, path_ratio;
  for (std::size_t i = 0; i < combined.size(); ++i) {
    const GoalCase& c = combined[i];
    if (!in(c)) continue;
    ++row.walkers;
    row.with_heading += c.has_heading ? 1 : 0;
    row.off_30deg += c.exit_off_heading_deg > kTurnDeg ? 1 : 0;
    row.off_45deg += c.exit_off_heading_deg > kSharpTurnDeg ? 1 : 0;
    row.path_ratio_above_1_2 += c.remaining_path_ratio > kDetourRatio ? 1 : 0;
    off_deg.push_back(c.exit_off_heading_deg);
    path_ratio.push_back(c.remaining_path_ratio);
    row.heading_correct += c.heading_correct ? 1 : 0;
    row.path_correct += path[i].correct ? 1 : 0;
    row.combined_correct += c.correct ? 1 : 0;
    row.either_correct += path[i].correct || c.heading_correct ? 1 : 0;
  }
  row.median_off_heading_deg = population::median(off_deg);
  row.median_path_ratio = population::median(path_ratio);
  return row;
}

}  // namespace

GoalReport evaluateGoalReport(const std::vector<PedestrianPair>& pairs,
                              std::optional<double> beta_per_m, const GoalEvalOptions& base) {
  GoalReport r;
  r.beta_given = beta_per_m.has_value();
  for (const ExitClustering how : {ExitClustering::kGreedyRadius, ExitClustering::kChained}) {
    for (const bool freq : {false, true}) {
      GoalEvalOptions o = base;
      o.clustering = how;
      o.frequency_prior = freq;
      o.heading_term = false;
      r.configs.push_back(evaluateConfig(pairs, beta_per_m, o));
    }
  }
  GoalEvalOptions o = base;
  o.clustering = ExitClustering::kChained;
  o.frequency_prior = true;
  o.heading_term = true;
  r.configs.push_back(evaluateConfig(pairs, beta_per_m, o));

  const auto path = heldOutCases(r.configs[3]);
  const auto combined = heldOutCases(r.configs[4]);
  const auto turns = [](const GoalCase& c) { return c.exit_off_heading_deg > kTurnDeg; };
  r.ceiling.push_back(ceilingRow("all", path, combined, [](const GoalCase&) { return true; }));
  for (const auto& ds : sequences(pairs)) {
    r.ceiling.push_back(
        ceilingRow(ds, path, combined, [&](const GoalCase& c) { return c.ds == ds; }));
  }
  const GoalCeilingRow straight =
      ceilingRow("exit <= 30 deg off heading at t (goes straight on)", path, combined,
                 [](const GoalCase& c) { return c.exit_off_heading_deg <= kTurnDeg; });
  const GoalCeilingRow& all = r.ceiling.front();
  r.straight_on_perfect_bound =
      ratio(straight.walkers + all.path_correct - straight.path_correct, all.walkers);
  r.ceiling.push_back(straight);
  r.ceiling.push_back(ceilingRow("exit > 30 deg off (turns after t)", path, combined, turns));
  r.ceiling.push_back(ceilingRow("exit > 45 deg off", path, combined, [](const GoalCase& c) {
    return c.exit_off_heading_deg > kSharpTurnDeg;
  }));
  r.ceiling.push_back(
      ceilingRow("no heading at t (first seen at t, or standing)", path, combined,
                 [](const GoalCase& c) { return !std::isfinite(c.exit_off_heading_deg); }));
  return r;
}

std::string formatGoalReport(const GoalReport& r) {
  std::string out;
  if (r.configs.empty()) return out;
  const GoalEvalOptions& o0 = r.configs.front().options;
  out += "Goal inference on real pedestrians: most likely goal at t = t_cross - " +
         fmt("%.1f", o0.lead_s) + " s vs where the walker leaves the scene\n";
  out +=
      "candidates: exits of the other walkers of the sequence (leave-pair-out), cluster radius " +
      fmt("%.2f", o0.cluster_radius_m) + " m; Euclidean (open space)\n";
  out += "heading at t: displacement over the last " + fmt("%.1f", o0.heading_window_s) +
         " s (none below " + fmt("%.2f", o0.min_heading_step_m) + " m)\n";
  out += r.beta_given ? "beta: given; kappa: leave-one-sequence-out\n\n"
                      : "beta (and kappa): leave-one-sequence-out (max mean ln P(true goal) on the "
                        "others)\n\n";
  out +=
      "| clustering + prior | beta (all) | kappa (all) | fit per fold (without it) | no candidate "
      "| accuracy (all) | accuracy (with candidate) | per sequence |\n"
      "|---|---:|---:|---|---:|---:|---:|---|\n";
  for (const auto& c : r.configs) {
    std::string fits, per_ds;
    for (const auto& f : c.folds) {
      fits += (fits.empty() ? "" : ", ") + f.held_out_ds + " beta " + fmt("%.1f", f.beta_per_m) +
              (c.options.heading_term ? " kappa " + fmt("%.1f", f.heading_kappa) : "");
      per_ds += (per_ds.empty() ? "" : ", ") + f.held_out_ds + " " +
                count(f.held_out.correct, f.held_out.walkers);
    }
    out += "| " + configName(c.options) + " | " + fmt("%.1f", c.options.beta_per_m) + " | " +
           (c.options.heading_term ? fmt("%.1f", c.options.heading_kappa) : "-") + " | " + fits +
           " | " + std::to_string(c.walkers - c.with_candidate) + " / " +
           std::to_string(c.walkers) + " | " + count(c.correct, c.walkers) + " | " +
           fmt("%.3f", c.accuracy_with_candidate) + " | " + per_ds + " |\n";
  }
  out +=
      "\nbeta sweep (all pairs; accuracy over all walkers, mean ln P(true goal); heading: kappa "
      "of its fit):\n";
  out += "| beta [1/m] |";
  for (const auto& c : r.configs) out += " " + configName(c.options) + " |";
  out += "\n|---:|";
  for (std::size_t k = 0; k < r.configs.size(); ++k) out += "---|";
  out += "\n";
  const auto betas = goalBetasPerM();
  for (std::size_t b = 0; b < betas.size(); ++b) {
    out += "| " + fmt("%.1f", betas[b]) + " |";
    for (const auto& c : r.configs) {
      const GoalEvaluation& e = c.sweep[b];
      out += " " + fmt("%.3f", e.accuracy_all) + " / " + fmt("%.3f", e.mean_log_p_true) + " |";
    }
    out += "\n";
  }
  for (const auto& c : r.configs) {
    if (c.kappa_sweep.empty()) continue;
    out += "\nkappa sweep (" + configName(c.options) + ", all pairs, beta " +
           fmt("%.1f", c.options.beta_per_m) +
           "):\n| kappa | accuracy (all) | mean ln P(true goal) |\n|---:|---:|---:|\n";
    const auto kappas = goalHeadingKappas();
    for (std::size_t k = 0; k < kappas.size(); ++k) {
      out += "| " + fmt("%.1f", kappas[k]) + " | " + fmt("%.3f", c.kappa_sweep[k].accuracy_all) +
             " | " + fmt("%.3f", c.kappa_sweep[k].mean_log_p_true) + " |\n";
    }
  }

  out +=
      "\nwhat the track up to t can tell: heading at t vs the straight direction to the walker's "
      "exit, rest of its track / straight distance; held-out accuracy of the heading predictor "
      "(cluster with the exit best aligned with the heading), of the path-length posterior "
      "(chained + exit-frequency prior), of it with the heading term, and of an oracle picking "
      "whichever of the first two is right:\n";
  out +=
      "| walkers | n | exit > 30 deg off heading | > 45 deg | median off [deg] | median rest / "
      "straight | rest > 1.2 x straight | heading predictor | path length | path length + heading "
      "| either (oracle) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& row : r.ceiling) {
    out += "| " + row.name + " | " + std::to_string(row.walkers) + " | " +
           count(row.off_30deg, row.walkers) + " | " + count(row.off_45deg, row.walkers) + " | " +
           fmt("%.1f", row.median_off_heading_deg) + " | " + fmt("%.2f", row.median_path_ratio) +
           " | " + count(row.path_ratio_above_1_2, row.walkers) + " | " +
           count(row.heading_correct, row.walkers) + " | " + count(row.path_correct, row.walkers) +
           " | " + count(row.combined_correct, row.walkers) + " | " +
           count(row.either_correct, row.walkers) + " |\n";
  }
  out +=
      "bound: every walker whose exit is within 30 deg of its heading at t right, the others as "
      "the path-length posterior has them: " +
      fmt("%.3f", r.straight_on_perfect_bound) + "\n\n";
  for (const auto& c : r.configs) {
    out += "goal accuracy at t_cross-" + fmt("%.0f", c.options.lead_s) +
           "s: " + fmt("%.3f", c.accuracy_all) + " (" + configName(c.options) +
           ", all walkers; with a candidate " + fmt("%.3f", c.accuracy_with_candidate) + ")\n";
  }
  const GoalConfigResult& path = r.configs[3];     // chained + exit-frequency prior
  const GoalConfigResult& heading = r.configs[4];  // the same + heading term
  out += "RESULT goal_accuracy_all " + fmt("%.3f", path.accuracy_all) + "\n";
  out += "RESULT goal_accuracy_with_candidate " + fmt("%.3f", path.accuracy_with_candidate) + "\n";
  out += "RESULT goal_no_candidate " + std::to_string(path.walkers - path.with_candidate) + "\n";
  out += "RESULT goal_accuracy_heading_term " + fmt("%.3f", heading.accuracy_all) + "\n";
  if (!r.ceiling.empty()) {
    const GoalCeilingRow& all = r.ceiling.front();
    out += "RESULT goal_exit_off_heading_30deg " + fmt("%.3f", ratio(all.off_30deg, all.walkers)) +
           "\n";
    out += "RESULT goal_exit_off_heading_45deg " + fmt("%.3f", ratio(all.off_45deg, all.walkers)) +
           "\n";
    out += "RESULT goal_accuracy_heading_predictor " +
           fmt("%.3f", ratio(all.heading_correct, all.walkers)) + "\n";
    out += "RESULT goal_accuracy_either_oracle " +
           fmt("%.3f", ratio(all.either_correct, all.walkers)) + "\n";
  }
  out += "RESULT goal_bound_straight_on_perfect " + fmt("%.3f", r.straight_on_perfect_bound) + "\n";
  return out;
}

}  // namespace coopnav::ctl
