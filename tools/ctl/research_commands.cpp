// coopnav_ctl's research evaluation (command.hpp): the assessment, its calibration, the forecast
// and goal inference scored on real head-on pedestrian pairs (/work/shared/pedestrians, as
// headon_pairs.json), and the candidate goals of a map.
//   pedestrians PAIRS [--gamma-per-s G] [--tau T] [--side-rule R] [--window W] [--lead-s S]
//               [--decision-time] [--daemon [--path-assessor BIN] [--profile P] [--config F]
//               [--set K=V]... [--lcm-url URL]]
//   calibrate PAIRS
//   forecast PAIRS [--write-profile FILE]
//   goals PAIRS [--beta-per-m B]
//   goal-candidates MAP
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>

#include "command.hpp"
#include "coopnav/distance/grid_distance_field.hpp"
#include "coopnav/planning/goal_inference.hpp"
#include "goals.hpp"
#include "maps/map_loader.hpp"
#include "pedestrians.hpp"
#include "pedestrians_daemon.hpp"
#include "pedestrians_forecast.hpp"

namespace coopnav::ctl {
namespace {

class PedestriansCommand final : public Command {
 public:
  explicit PedestriansCommand(CLI::App& sub) {
    sub.add_option("pairs", pairs_, "headon_pairs.json")->required();
    sub.add_option("--gamma-per-s", gamma_per_s_, "gamma per second (default 0.98^10)")
        ->check(CLI::PositiveNumber);
    sub.add_option("--tau", tau_m_, "tau [m] (default 0.4)");
    sub.add_option("--side-rule", side_rule_, "CA sign rule (default path_side)")
        ->check(CLI::IsMember({"path_side", "human_side"}));
    sub.add_option("--window", window_,
                   "where the CM window starts: round1 (t0, the paper's), onset (the walker's "
                   "avoidance onset), lead (--lead-s before the closest approach)")
        ->check(CLI::IsMember({"round1", "onset", "lead"}));
    sub.add_option("--lead-s", lead_s_, "lead window length [s] (default 2)")
        ->check(CLI::PositiveNumber);
    sub.add_flag("--daemon", daemon_,
                 "run the walkers through a spawned coopnav_path_assessor over LCM and compare "
                 "with the in-process replay (exit 1 when they differ)");
    auto& d = daemon_options_;
    sub.add_option("--path-assessor", d.path_assessor,
                   "--daemon: the daemon binary (default: the build tree's)");
    sub.add_option("--profile", d.profile,
                   "--daemon: config/path_assessor.yaml (paper) or "
                   "config/path_assessor_calibrated.yaml (calibrated)")
        ->check(CLI::IsMember({"paper", "calibrated"}));
    sub.add_option("--config", d.config_path, "--daemon: the daemon's config file");
    sub.add_option("--set", d.overrides, "--daemon: key=value for the daemon (repeatable)")
        ->allow_extra_args(false);
    sub.add_option(
        "--lcm-url", d.lcm_url,
        std::string("--daemon: a private LCM URL (default ") + kPedestrianDaemonUrl + ")");
    sub.add_flag("--decision-time", decision_time_,
                 "also the judgement's AUC and accuracy at t_cross - {4, 3, 2, 1, 0} s, per "
                 "sequence, with bootstrap intervals");
  }

  int run(const std::string&) override {
    WindowSetting window;
    window.kind = windowKindFromString(window_).value_or(window.kind);
    window.lead_s = lead_s_;
    const auto pairs = loadPedestrianPairs(pairs_);
    if (daemon_) return runThroughDaemon(pairs, window);
    // The paper profile unless given: γ 0.98 per 0.1 s sample exactly, τ 0.4 m, path side.
    assessment::PathAssessorConfig config;
    if (gamma_per_s_) config.gamma = gammaPerSample(*gamma_per_s_, config.sample_period_s);
    config.tau_m = tau_m_.value_or(config.tau_m);
    if (side_rule_)
      config.side_rule = assessment::sideRuleFromString(*side_rule_).value_or(config.side_rule);
    if (decision_time_) {
      // The settings given (no fit here): the judgement read at t_cross - {4 .. 0} s.
      std::cout << formatDecisionTables({scoreJudgements("CM", "the settings above, round-1 window",
                                                         pairs, cmJudgements(pairs, config))});
    }
    const auto e = evaluateWalkers(pairs, config, window);
    std::cout << formatPedestrianEvaluation(
        e, gamma_per_s_.value_or(std::pow(config.gamma, 1.0 / config.sample_period_s)), window);
    return 0;
  }

 private:
  // The daemon runs with its config file; the settings given here become its --set overrides.
  int runThroughDaemon(const std::vector<PedestrianPair>& pairs, const WindowSetting& window) {
    DaemonRunOptions d = daemon_options_;
    std::vector<std::string> sets;
    char buf[64];
    if (gamma_per_s_) {
      std::snprintf(
          buf, sizeof buf, "gamma=%.17g",
          gammaPerSample(*gamma_per_s_, assessment::PathAssessorConfig{}.sample_period_s));
      sets.emplace_back(buf);
    }
    if (tau_m_) {
      std::snprintf(buf, sizeof buf, "tau_m=%.17g", *tau_m_);
      sets.emplace_back(buf);
    }
    if (side_rule_) sets.push_back("side_rule=" + *side_rule_);
    d.overrides.insert(d.overrides.begin(), sets.begin(), sets.end());
    const auto r = runPedestriansThroughDaemon(pairs, window, d);
    std::cout << formatDaemonRun(r, window);
    return r.sample_mismatches == 0 && r.max_abs_dcm_m <= kDaemonAgreementM ? 0 : 1;
  }

  std::string pairs_;
  std::optional<double> gamma_per_s_;
  std::optional<double> tau_m_;
  std::optional<std::string> side_rule_;
  std::string window_{"round1"};
  double lead_s_{2.0};
  bool decision_time_{false};
  bool daemon_{false};
  DaemonRunOptions daemon_options_;
};

class CalibrateCommand final : public Command {
 public:
  explicit CalibrateCommand(CLI::App& sub) {
    sub.add_option("pairs", pairs_, "headon_pairs.json")->required();
  }

  int run(const std::string&) override {
    std::cout << formatCalibration(calibrate(loadPedestrianPairs(pairs_)));
    return 0;
  }

 private:
  std::string pairs_;
};

class ForecastCommand final : public Command {
 public:
  explicit ForecastCommand(CLI::App& sub) {
    sub.add_option("pairs", pairs_, "headon_pairs.json")->required();
    sub.add_option("--write-profile", profile_out_,
                   "write the forecast fitted on all pairs (config/path_assessor_forecast.yaml)");
  }

  int run(const std::string&) override {
    const auto pairs = loadPedestrianPairs(pairs_);
    const auto study = runForecastStudy(pairs, calibrate(pairs));
    std::cout << formatForecastStudy(study);
    if (!profile_out_.empty()) {
      std::ofstream out(profile_out_);
      out << forecastProfileYaml(study.model);
      if (!out) {
        std::cerr << profile_out_ << ": cannot write\n";
        return 1;
      }
      std::cout << "wrote " << profile_out_ << "\n";
    }
    return 0;
  }

 private:
  std::string pairs_;
  std::string profile_out_;
};

class GoalsCommand final : public Command {
 public:
  explicit GoalsCommand(CLI::App& sub) {
    sub.add_option("pairs", pairs_, "headon_pairs.json")->required();
    sub.add_option("--beta-per-m", beta_per_m_, "beta [1/m] (default: fit by sequence)")
        ->check(CLI::PositiveNumber);
  }

  int run(const std::string&) override {
    std::cout << formatGoalReport(evaluateGoalReport(loadPedestrianPairs(pairs_), beta_per_m_));
    return 0;
  }

 private:
  std::string pairs_;
  std::optional<double> beta_per_m_;  // fit leave-one-sequence-out unless given
};

/// The candidate goals the band source's goal inference would start from on a map (default
/// options): from the map's shape, then annotated on it (goal_regions).
class GoalCandidatesCommand final : public Command {
 public:
  explicit GoalCandidatesCommand(CLI::App& sub) {
    sub.add_option("map", map_, "map file (ROS map YAML, walls YAML, scenario)")
        ->required()
        ->check(CLI::ExistingFile);
  }

  int run(const std::string&) override {
    LoadedMap loaded = loadMap(map_);
    const GridDistanceField field(std::move(loaded.grid));
    const auto print = [](const char* from, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
      const Eigen::Vector2d c = 0.5 * (a + b);
      std::printf("%-9s centre (%.2f, %.2f)  from (%.2f, %.2f) to (%.2f, %.2f)  %.2f m\n", from,
                  c.x(), c.y(), a.x(), a.y(), b.x(), b.y(), (b - a).norm());
    };
    for (const GoalRegion& r : mapGoalCandidates(field)) print("shape", r.a, r.b);
    for (const MapGoalRegion& r : loaded.goal_regions) print("annotated", r.a, r.b);
    return 0;
  }

 private:
  std::string map_;
};

}  // namespace

void addResearchCommands(CLI::App& app, CommandTable& table) {
  addCommand<PedestriansCommand>(app, table, "pedestrians",
                                 "score CM / IsContributing on real head-on pedestrian pairs");
  addCommand<CalibrateCommand>(
      app, table, "calibrate",
      "fit gamma, tau, the side rule and the window on pedestrian pairs (leave one sequence out)");
  addCommand<ForecastCommand>(
      app, table, "forecast",
      "judgement in time on pedestrian pairs: paper / calibrated CM and the p_contributing "
      "forecast at t_cross - {4 .. 0} s, leave one sequence out; fit the forecast profile");
  addCommand<GoalsCommand>(
      app, table, "goals",
      "score goal inference (most likely exit at t_cross - 3 s) on pedestrian pairs");
  addCommand<GoalCandidatesCommand>(
      app, table, "goal-candidates",
      "print the candidate goals of a map (its shape's openings and corridor ends, then its "
      "goal_regions), as the band source's goal inference finds them with default options");
}

}  // namespace coopnav::ctl
