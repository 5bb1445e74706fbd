#include "goals.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numeric>
#include <set>

#include "coopnav/planning/goal_inference.hpp"

namespace coopnav::ctl {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMinProbability = 1e-12;  ///< floor of p_true in the log score
constexpr double kTimeEps_s = 1e-9;

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

double fitBeta(const std::vector<PedestrianPair>& pairs, GoalEvalOptions o) {
  double best_beta = goalBetasPerM().front();
  double best = -std::numeric_limits<double>::infinity();
  for (const double beta : goalBetasPerM()) {
    o.beta_per_m = beta;
    const double score = evaluateGoalInference(pairs, o).mean_log_p_true;
    if (score > best) {
      best = score;
      best_beta = beta;
    }
  }
  return best_beta;
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

std::string configName(const GoalEvalOptions& o) {
  return std::string(toString(o.clustering)) +
         (o.frequency_prior ? " + exit-frequency prior" : " + uniform prior");
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
      for (std::size_t k = 0; k < t->t_s.size() && t->t_s[k] <= until_s; ++k) {
        if (belief.observe(t->t_s[k], {t->x_m[k], t->y_m[k]})) ++gc.observations;
      }
      if (gc.has_candidate) {
        gc.p_true = belief.probabilities()[static_cast<std::size_t>(truth)];
        gc.correct = belief.mostLikely() == truth;
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

GoalReport evaluateGoalReport(const std::vector<PedestrianPair>& pairs,
                              std::optional<double> beta_per_m, const GoalEvalOptions& base) {
  GoalReport r;
  r.beta_given = beta_per_m.has_value();
  for (const ExitClustering how : {ExitClustering::kGreedyRadius, ExitClustering::kChained}) {
    for (const bool freq : {false, true}) {
      GoalConfigResult c;
      c.options = base;
      c.options.clustering = how;
      c.options.frequency_prior = freq;
      for (const auto& ds : sequences(pairs)) {
        GoalFold f;
        f.held_out_ds = ds;
        GoalEvalOptions o = c.options;
        o.beta_per_m = beta_per_m ? *beta_per_m : fitBeta(without(pairs, ds), o);
        f.beta_per_m = o.beta_per_m;
        f.held_out = evaluateGoalInference(pairs, o, ds);
        c.walkers += f.held_out.walkers;
        c.with_candidate += f.held_out.with_candidate;
        c.correct += f.held_out.correct;
        c.folds.push_back(std::move(f));
      }
      c.accuracy_all = ratio(c.correct, c.walkers);
      c.accuracy_with_candidate = ratio(c.correct, c.with_candidate);
      c.options.beta_per_m = beta_per_m ? *beta_per_m : fitBeta(pairs, c.options);
      for (const double beta : goalBetasPerM()) {
        GoalEvalOptions o = c.options;
        o.beta_per_m = beta;
        c.sweep.push_back(evaluateGoalInference(pairs, o));
      }
      r.configs.push_back(std::move(c));
    }
  }
  return r;
}

std::string formatGoalReport(const GoalReport& r) {
  std::string out;
  if (r.configs.empty()) return out;
  const GoalEvalOptions& o0 = r.configs.front().options;
  out += "Goal inference on real pedestrians: most likely goal at t_cross - " +
         fmt("%.1f", o0.lead_s) + " s vs where the walker leaves the scene\n";
  out +=
      "candidates: exits of the other walkers of the sequence (leave-pair-out), cluster radius " +
      fmt("%.2f", o0.cluster_radius_m) + " m; Euclidean (open space)\n";
  out += r.beta_given ? "beta: given\n"
                      : "beta: leave-one-sequence-out (max mean ln P(true goal) on the others)\n\n";
  out +=
      "| clustering + prior | beta (all) | beta per fold (fit without it) | no candidate | "
      "accuracy (all) | "
      "accuracy (with candidate) | per sequence |\n|---|---:|---|---:|---:|---:|---|\n";
  for (const auto& c : r.configs) {
    std::string betas, per_ds;
    for (const auto& f : c.folds) {
      betas += (betas.empty() ? "" : ", ") + f.held_out_ds + " " + fmt("%.1f", f.beta_per_m);
      per_ds += (per_ds.empty() ? "" : ", ") + f.held_out_ds + " " +
                fmt("%.3f", f.held_out.accuracy_all) + " (" + std::to_string(f.held_out.correct) +
                "/" + std::to_string(f.held_out.walkers) + ")";
    }
    out += "| " + configName(c.options) + " | " + fmt("%.1f", c.options.beta_per_m) + " | " +
           betas + " | " + std::to_string(c.walkers - c.with_candidate) + " / " +
           std::to_string(c.walkers) + " | " + fmt("%.3f", c.accuracy_all) + " (" +
           std::to_string(c.correct) + "/" + std::to_string(c.walkers) + ") | " +
           fmt("%.3f", c.accuracy_with_candidate) + " | " + per_ds + " |\n";
  }
  out += "\nbeta sweep (all pairs; accuracy over all walkers, mean ln P(true goal)):\n";
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
  out += "\n";
  for (const auto& c : r.configs) {
    out += "goal accuracy at t_cross-" + fmt("%.0f", c.options.lead_s) +
           "s: " + fmt("%.3f", c.accuracy_all) + " (" + configName(c.options) +
           ", all walkers; with a candidate " + fmt("%.3f", c.accuracy_with_candidate) + ")\n";
  }
  const GoalConfigResult& best = r.configs.back();  // chained + exit-frequency prior
  out += "RESULT goal_accuracy_all " + fmt("%.3f", best.accuracy_all) + "\n";
  out += "RESULT goal_accuracy_with_candidate " + fmt("%.3f", best.accuracy_with_candidate) + "\n";
  out += "RESULT goal_no_candidate " + std::to_string(best.walkers - best.with_candidate) + "\n";
  return out;
}

}  // namespace coopnav::ctl
