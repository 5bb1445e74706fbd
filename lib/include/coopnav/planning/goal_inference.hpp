#pragma once
/// @file Goal inference for tracked humans whose goal is not given (the paper §II-A
/// assumes known goals). Candidate goals come from the map (openings where free space meets the
/// map's border, dead ends of the free space's skeleton: corridor ends) and from a configured
/// list; a posterior over them follows the observed track with the path-length likelihood of
/// goal prediction in human-aware navigation (Dragan & Srinivasa's legibility model, the one
/// CoHAN's goal prediction and MDP-style predictors use):
///
///   P(g | ξ_{s→q}) ∝ P(g) · exp(−β (|ξ_{s→q}| + L(q, g))) / exp(−β L(s, g))
///
/// |ξ| the length walked so far, L the shortest free-space path length (geodesic on the map,
/// Euclidean without one). Pure logic: positions and times come from the caller.

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <vector>

#include "coopnav/distance/distance_map.hpp"

namespace coopnav {

/// Largest search / distance grid (cells) of mapGoalCandidates and GoalDistances (4096²).
inline constexpr std::size_t kMaxGoalGridCells = std::size_t{1} << 24;

/// A place people walk to: a segment across a corridor's end or along an opening, or a point
/// (a == b). People leave a corridor anywhere across its end, so a walker's goal in it is where
/// it crosses the segment, not its centre: heading for the centre would make its "shortest path"
/// a diagonal across the corridor, and a walker keeping its lane would read as deviating.
struct GoalRegion {
  Eigen::Vector2d a{0.0, 0.0};
  Eigen::Vector2d b{0.0, 0.0};

  static GoalRegion point(const Eigen::Vector2d& p) { return {p, p}; }
  Eigen::Vector2d centre() const { return 0.5 * (a + b); }
  double length_m() const { return (b - a).norm(); }
  /// The point of the segment nearest to p.
  Eigen::Vector2d closest(const Eigen::Vector2d& p) const { return target(p, 0.0); }
  /// Where a walker at p crosses the region keeping its place across it: p's projection onto
  /// the segment, at least inset_m from its ends (the centre of a segment shorter than 2 inset_m).
  Eigen::Vector2d target(const Eigen::Vector2d& p, double inset_m) const;
};

struct GoalCandidateOptions {
  double agent_radius_m{0.3};         ///< free space = clearance >= this
  double resolution_m{0.1};           ///< grid the candidates are searched on
  double min_separation_m{1.5};       ///< candidates closer than this merge (the first kept)
  double opening_inset_m{0.3};        ///< an opening's candidate sits this far inside the map
  double min_dead_end_length_m{1.0};  ///< skeleton branches shorter than this are noise
};

/// Candidate goals of a map: the openings (runs of free border cells, sides in the order bottom,
/// right, top, left; the region runs along the run, opening_inset_m inside the map) and the ends
/// of the skeleton's branches (corridor ends, in raster order; the region runs across the
/// corridor through the end, as far as free space reaches), merged when their centres lie within
/// min_separation_m (the first kept), so openings come first. Deterministic for one map and
/// options. Empty when the search grid would exceed kMaxGoalGridCells or nothing is free.
///
/// Skeleton: a cell is a ridge cell when its nearest obstacle point and a 4-neighbour's lie at
/// least max(2 cells, its clearance) apart (the integer medial axis, Hesselink & Roerdink 2008,
/// doi:10.1109/TPAMI.2007.70757), thinned to one cell (Zhang & Suen 1984,
/// doi:10.1145/357994.358023). Leaf branches are pruned while they end at the edge of free
/// space (clearance below agent_radius_m + 2.5 cells: branches into room corners, to bumps on
/// walls) or their length minus √2 × their drop in clearance (what a branch along a corner's
/// bisector has) is below min_dead_end_length_m; the ends that remain are corridor ends. A hall
/// whose skeleton is all loops (open.pgm) has none: give such maps a configured goal list.
std::vector<GoalRegion> mapGoalCandidates(const DistanceMap& map,
                                          const GoalCandidateOptions& options = {});

struct GoalInferenceOptions {
  double beta_per_m{1.0};        ///< rationality [1/m]: how sharply a detour counts against a goal
  double resolution_m{0.1};      ///< geodesic grid (map mode)
  double agent_radius_m{0.3};    ///< passable geodesic cells have this clearance [m]
  double min_step_m{0.05};       ///< track steps shorter than this are jitter, not walking
  double reached_radius_m{0.5};  ///< a goal the human is within is not "ahead" (prob. to 0)
};

/// Per-goal distance fields (Dijkstra from every candidate region on the free-space grid, once at
/// construction) so that a cycle's L(q, g), the way to the nearest point of the region, is a
/// lookup; without a map, Euclidean distances to the segment.
/// Grid: cells of options.resolution_m (at least the map's) over the map's bounds; 8-connected
/// moves between cells with clearance >= agent_radius_m; cells with less (but > 0) clearance,
/// where people do walk close to walls, get the distance of a passable cell within
/// agent_radius_m + one cell plus the way there, but never pass it on to passable cells, so no
/// path runs through a gap narrower than the agent. A goal in such a cell starts from the
/// passable cells within that distance; a segment seeds along its length. Memory: 4 B per cell and
/// goal. A grid larger than kMaxGoalGridCells makes every distance +inf. Immutable after
/// construction: const calls are safe from several threads.
class GoalDistances {
 public:
  /// map == nullptr: open space, Euclidean distances.
  GoalDistances(std::shared_ptr<const DistanceMap> map, std::vector<GoalRegion> goals,
                const GoalInferenceOptions& options = {});
  /// Point goals.
  GoalDistances(std::shared_ptr<const DistanceMap> map, const std::vector<Eigen::Vector2d>& goals,
                const GoalInferenceOptions& options = {});
  const std::vector<GoalRegion>& goals() const { return goals_; }
  /// The options in force (resolution_m raised to the map's).
  const GoalInferenceOptions& options() const { return options_; }
  /// Shortest free-space length from p to goal i [m] (bilinear between the finite cell values
  /// around p); +inf when unreachable, outside the map, non-finite, or goal >= goals().size().
  /// O(1).
  double distance(std::size_t goal, const Eigen::Vector2d& p) const;
  /// True when distances are geodesic on a map (false: Euclidean, map == nullptr).
  bool geodesic() const { return map_ != nullptr; }

 private:
  std::shared_ptr<const DistanceMap> map_;
  std::vector<GoalRegion> goals_;
  GoalInferenceOptions options_;
  Eigen::Vector2d origin_{0.0, 0.0};
  int nx_{0};
  int ny_{0};
  std::vector<std::vector<float>> field_m_;  ///< per goal, per cell; +inf unreachable
};

/// The belief about one human's goal, updated from its track. Since |ξ_{s→q}| is the same for
/// every goal, the posterior is log P(g | ξ) = log P(g) − β (L(q, g) − L(s, g)) + const: one
/// distance lookup per goal and observation, computed in log space (log-sum-exp). A goal
/// unreachable from s or q gets 0 (all unreachable: the prior); a goal within reached_radius_m
/// of q gets 0 unless no other goal is left. While every goal is unreachable from the
/// observations (a human outside the map), the start waits for the first position from which
/// one is reachable.
class GoalBelief {
 public:
  /// distances == nullptr: no candidate. prior: one weight >= 0 per goal, not all 0 (normalised
  /// here); empty or invalid: uniform.
  explicit GoalBelief(std::shared_ptr<const GoalDistances> distances,
                      std::vector<double> prior = {});
  /// Adds an observed position (times strictly increasing; a non-finite or older one is
  /// ignored and false returned). A step shorter than min_step_m from the last position used is
  /// accepted (true) but does not move it. O(number of goals).
  bool observe(double t_s, const Eigen::Vector2d& position);
  /// P(goal i | track): the prior before the first observation; from the first observation on,
  /// unreachable and reached goals at 0 (at the start L(q, g) = L(s, g), so the prior otherwise).
  const std::vector<double>& probabilities() const { return probability_; }
  /// Index of the most likely goal; -1 when there is no candidate. On a map, goals within
  /// exp(−β √2 resolution_m) of the most probable one are tied (path-length differences below a
  /// diagonal grid step are the grid's, not evidence): a walk down a corridor fits every place
  /// beyond its end or its next junction alike. The tie goes to the goal whose shortest path from
  /// the last position used is the straightest (the least longer than the straight line to the
  /// region's nearest point, within a diagonal grid step: people go on straight unless they
  /// turn), then to the nearest, then to the lowest index.
  int mostLikely() const;
  /// The goal to plan with when `current` is planned with now: current, unless the most likely
  /// goal's path-length evidence beats it by more than switch_margin_m (log-odds > β × margin)
  /// or current is out of range or at probability 0; then mostLikely(). An avoidance step is
  /// evidence too (stepping towards a wall brings the places behind it nearer), and re-planning
  /// on it would move the reference path, the path the human would have walked, with the
  /// avoidance it is there to measure.
  int plannedGoal(int current, double switch_margin_m) const;
  double walkedLength_m() const { return walked_m_; }
  std::size_t observations() const { return observations_; }

 private:
  void recompute();

  std::shared_ptr<const GoalDistances> distances_;
  std::vector<double> prior_;
  std::vector<double> probability_;
  std::vector<double> start_distance_m_;  ///< L(s, g) per goal
  Eigen::Vector2d start_{0.0, 0.0};
  Eigen::Vector2d last_{0.0, 0.0};
  double last_t_s_{0.0};
  double walked_m_{0.0};
  std::size_t observations_{0};
  bool anchored_{false};            ///< start_ set (some goal reachable from it)
  std::vector<double> distance_m_;  ///< L(q, g) per goal at the last observation
};

}  // namespace coopnav
