#pragma once
/// @file The population generator: N head-on corridor encounters in the scenario format of
/// docs/scenario-format.md, drawn from one seed. Header-only (no library to link) so that the
/// unit tests in test/unit/population check exactly what coopnav_population writes.
///
/// Determinism: every draw comes from SplitMix64 (Steele, Lea & Flood 2014, doi
/// 10.1145/2714064.2660195) turned into doubles by its top 53 bits; no std:: distribution (their
/// algorithms differ between standard libraries) and every number is written with a fixed
/// printf format, so a seed gives the same files byte for byte on any machine.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace coopnav::population {

/// SplitMix64: a 64-bit state advanced by a constant, mixed on output.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1): the top 53 bits over 2^53.
  double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  /// Uniform in {0, ..., n - 1}; n >= 1.
  std::size_t index(std::size_t n) {
    return static_cast<std::size_t>(unit() * static_cast<double>(n));
  }

 private:
  std::uint64_t state_;
};

/// Rounds to a multiple of `step` (1 / step an integer), dividing by 1 / step so that the result
/// is the double nearest the decimal (35 / 100 is 0.35; 35 * 0.01 is not).
inline double quantize(double v, double step) {
  const double per_unit = std::round(1.0 / step);
  return std::round(v * per_unit) / per_unit;
}

inline std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

/// The behaviours of docs/scenario-format.md, in the order the generator cycles through them.
inline const std::array<const char*, 6>& behaviourNames() {
  static const std::array<const char*, 6> k{"facilitating",      "minimal",      "oblivious",
                                            "late_facilitating", "social_force", "responsive"};
  return k;
}

/// A straight stretch the encounters happen in. The robot drives +x along centre_y_m from
/// robot_start_x_m to robot_goal_x_m; humans keep lateral_min_y_m..lateral_max_y_m (their
/// centres, clear of the walls by radius + a margin).
struct Layout {
  std::string key;       ///< e.g. "corridor_1.70", "open_narrow"; names the baseline run
  std::string map_file;  ///< copied map ("open.yaml"), empty for a synthetic corridor
  double width_m{0.0};   ///< clear width of the stretch
  double centre_y_m{0.0};
  double robot_start_x_m{0.0};
  double robot_goal_x_m{0.0};
  double lateral_min_y_m{0.0};
  double lateral_max_y_m{0.0};
  /// Head-on human: starts robot_goal_x_m + [head_start_min, head_start_max], walks to
  /// head_goal_x_m (just behind the robot's start, as in the paper's scenarios).
  double head_start_min_m{0.5};
  double head_start_max_m{2.0};
  double head_goal_x_m{0.0};
  double follower_goal_x_m{0.0};  ///< the human behind the head-on one walks to here
  double same_way_goal_x_m{0.0};  ///< the human walking the robot's way walks to here
  /// Lanes of the extra humans (open_wide: round the pillar); empty = the corridor's own range.
  std::vector<std::pair<double, double>> extra_lanes_y_m;
  /// Where people go in the map, for goal inference with goals withheld (the map section's
  /// goal_regions: {x0, y0, x1, y1} [m]); empty: the map's shape shows them.
  std::vector<std::array<double, 4>> goal_regions_m;
  /// Synthetic corridor: x extent of its closed end walls.
  double wall_x0_m{0.0};
  double wall_x1_m{0.0};
};

constexpr double kRobotRadiusM = 0.47;  // scenario default (CoHAN's PR2)
constexpr double kHumanRadiusM = 0.3;   // scenario default
constexpr double kStartMarginM = 0.1;   // beyond the radius, from the walls, at the start

/// Synthetic straight corridors: from the narrowest a 0.94 m robot and a 0.6 m human can pass in
/// (1.54 m plus margins) to the paper's open 6 m. Fixed widths so that the run without humans
/// is shared by every encounter of a width.
inline const std::vector<double>& syntheticWidthsM() {
  static const std::vector<double> k{1.70, 1.80, 1.90, 2.00, 2.25, 2.50,
                                     2.75, 3.00, 3.50, 4.00, 5.00, 6.00};
  return k;
}

inline Layout syntheticCorridor(double width_m) {
  Layout l;
  l.key = "corridor_" + fmt("%.2f", width_m);
  l.width_m = width_m;
  l.centre_y_m = quantize(width_m / 2.0, 0.005);
  l.robot_start_x_m = 3.0;
  l.robot_goal_x_m = 27.0;
  l.lateral_min_y_m = kHumanRadiusM + kStartMarginM;
  l.lateral_max_y_m = width_m - kHumanRadiusM - kStartMarginM;
  l.head_goal_x_m = 2.5;
  l.follower_goal_x_m = 1.0;
  l.same_way_goal_x_m = 33.0;
  l.wall_x0_m = -1.0;
  l.wall_x1_m = 34.0;
  return l;
}

/// open.pgm is a closed hall whose skeleton is all loops: the places people go in it are the
/// mouths of its two corridors at the divider's ends (x 9.65 and 35.30), as the paper's narrow
/// scenarios annotate them.
inline const std::vector<std::array<double, 4>>& openPgmGoalRegionsM() {
  static const std::vector<std::array<double, 4>> k{{9.65, 0.45, 9.65, 2.70},
                                                    {35.30, 0.45, 35.30, 2.70},
                                                    {9.65, 3.50, 9.65, 9.50},
                                                    {35.30, 3.50, 35.30, 9.50}};
  return k;
}

/// The straight stretches of the real maps (geometry measured from the pixels of the maps the
/// population reads, their credit in test/data/maps/CREDIT.md; junctions: y 25.00-27.00 free from
/// x 6.85 to 37.50, crossed by a 1.5 m corridor at x 23.50-25.00).
/// junctions.pgm's 2.0 m corridor (y 25.00-27.00): its map, width and the lanes people start in;
/// the head-on layout and the junction crowd layout both go along it.
inline Layout junctionsCorridor() {
  Layout l;
  l.map_file = "junctions.yaml";
  l.width_m = 2.0;
  l.centre_y_m = 26.0;
  l.lateral_min_y_m = 25.0 + kHumanRadiusM + kStartMarginM;
  l.lateral_max_y_m = 27.0 - kHumanRadiusM - kStartMarginM;
  return l;
}

inline std::vector<Layout> mapLayouts() {
  std::vector<Layout> out;
  {
    Layout l;  // open.pgm, lower corridor y 0.45-2.70 (the paper's 2.25 m), x 9.65-35.30
    l.key = "open_narrow";
    l.map_file = "open.yaml";
    l.goal_regions_m = openPgmGoalRegionsM();
    l.width_m = 2.25;
    l.centre_y_m = 1.575;
    l.robot_start_x_m = 11.0;
    l.robot_goal_x_m = 34.0;
    l.lateral_min_y_m = 0.45 + kHumanRadiusM + kStartMarginM;
    l.lateral_max_y_m = 2.70 - kHumanRadiusM - kStartMarginM;
    l.head_goal_x_m = 10.5;
    l.follower_goal_x_m = 9.0;
    l.same_way_goal_x_m = 37.5;
    l.head_start_max_m = 2.0;
    out.push_back(l);
  }
  {
    // open.pgm, upper corridor y 3.50-9.50 (6 m), straight only for x 9.65-21.90 (then the
    // pillar): the robot starts in the west open area and the head-on human west of the pillar
    // (x <= 21.3 keeps it 0.3 m clear); the extra humans use the lanes round the pillar.
    Layout l;
    l.key = "open_wide";
    l.map_file = "open.yaml";
    l.goal_regions_m = openPgmGoalRegionsM();
    l.width_m = 6.0;
    l.centre_y_m = 6.5;
    l.robot_start_x_m = 2.5;
    l.robot_goal_x_m = 20.5;
    l.lateral_min_y_m = 6.2;
    l.lateral_max_y_m = 6.8;
    l.head_start_min_m = 0.3;
    l.head_start_max_m = 0.8;
    l.head_goal_x_m = 2.0;
    l.follower_goal_x_m = 1.5;
    l.same_way_goal_x_m = 30.0;
    l.extra_lanes_y_m = {{4.2, 4.7}, {8.3, 8.8}};
    out.push_back(l);
  }
  {
    Layout l = junctionsCorridor();
    l.key = "junctions_2.00";
    l.robot_start_x_m = 8.0;
    l.robot_goal_x_m = 33.0;
    l.head_start_max_m = 2.0;
    l.head_goal_x_m = 7.0;
    l.follower_goal_x_m = 5.0;
    l.same_way_goal_x_m = 37.0;
    out.push_back(l);
  }
  return out;
}

/// Every layout the generator draws from, synthetic first.
inline std::vector<Layout> allLayouts() {
  std::vector<Layout> out;
  for (double w : syntheticWidthsM()) out.push_back(syntheticCorridor(w));
  for (auto& l : mapLayouts()) out.push_back(l);
  return out;
}

/// One simulated human: role "head_on" (towards the robot), "follower" (behind the head-on one,
/// same direction) or "same_way" (ahead of the robot, walking its way).
struct HumanSpec {
  int id{1};
  std::string role;
  std::string behaviour;
  double start_x_m{0.0}, start_y_m{0.0}, goal_x_m{0.0}, goal_y_m{0.0};
  double speed_m_s{1.0};
  double velocity_noise_m_s{0.0};
  /// Behaviour params as (key, value); "group.key" is written nested ({group: {key: v}}).
  std::vector<std::pair<std::string, double>> params;
  /// Crowds only (generateCrowdPopulation): waypoints between start and goal, the start heading
  /// as written (empty: towards the goal along x, as the head-on encounters have it), and the
  /// group the human walks or stands with (0: alone).
  std::vector<std::array<double, 2>> via;
  std::string start_theta;
  int group{0};
  /// Pauses on the way (scenario key pause): stands pause_duration_s once it has walked
  /// pause_after_m along its path; 0 s = no pause.
  double pause_after_m{0.0};
  double pause_duration_s{0.0};
};

struct Encounter {
  std::string name;  ///< scenario name and file stem
  std::uint64_t seed{0};
  Layout layout;
  std::vector<HumanSpec> humans;
  std::string kind;  ///< crowd kind (crowdKindNames()); empty for a head-on encounter
  /// The robot drives differentially (turns to swerve) instead of holonomically; the band source
  /// must plan with the same kinematics (scripts/scenario.sh passes it from the scenario).
  bool differential{false};
  /// The humans are published as a people tracker sees them (trackerYaml()).
  bool tracker_noise{false};
  /// Head-on encounters: what the widened draw added ("abreast", "slower_ahead" or empty).
  std::string variant;
};

/// Ranges the generator draws from (docs/population.md lists them). All lie inside the
/// validated ranges of lib/include/coopnav/sim/behaviour.hpp, around its defaults.
struct Ranges {
  double speed_min_m_s{0.8}, speed_max_m_s{1.3};
  double head_on_offset_m{0.3};  ///< |lateral offset| of the head-on human from the centre
  double extra_offset_m{0.4};    ///< of the extra humans
  double noise_max_m_s{0.05};    ///< velocity_noise_m_s in [0, this]
  double follower_gap_min_m{2.0}, follower_gap_max_m{2.8};      ///< behind the head-on human
  double same_way_ahead_min_m{2.5}, same_way_ahead_max_m{4.5};  ///< ahead of the robot
  double two_humans_p{0.3}, three_humans_p{0.2};
  // Widened encounters (issue 44: what found the stalemates), drawn from each encounter's own
  // stream after the draws above, which they leave as they were.
  double differential_p{0.25};   ///< a differential-drive robot
  double tracker_noise_p{0.25};  ///< the humans through a people tracker (trackerYaml())
  double abreast_p{0.15};        ///< a second person abreast of the head-on one (a pair)
  double slower_ahead_p{0.15};   ///< a slower person ahead of the robot walking its way
  double abreast_spacing_min_m{0.7}, abreast_spacing_max_m{0.9};  ///< centre to centre
  double slower_speed_min_m_s{0.4}, slower_speed_max_m_s{0.6};    ///< below the robot's 0.7
  double slower_ahead_min_m{3.0}, slower_ahead_max_m{6.0};        ///< ahead of the robot
  /// One of the people (any, even odds) pauses on the way, after the draws above: stands for a
  /// while where it has walked pause_after_m, then goes on. Shorter than world_sim's standstill
  /// time (15 s), so that a robot waiting behind a paused person is not a standstill by itself.
  double pause_p{0.1};
  double pause_after_min_m{2.0}, pause_after_max_m{8.0};  ///< along its path (at most half)
  double pause_duration_min_s{3.0}, pause_duration_max_s{10.0};
  /// Only the layouts no wider than this are drawn from (a study of narrow corridors; the
  /// layout draw then differs from the full population's).
  double max_width_m{std::numeric_limits<double>::infinity()};
};

/// Draws a behaviour's params (2 decimals).
inline std::vector<std::pair<std::string, double>> drawParams(const std::string& behaviour,
                                                              Rng& rng) {
  auto u = [&](double lo, double hi) { return quantize(rng.uniform(lo, hi), 0.01); };
  if (behaviour == "minimal")
    return {{"horizon_s", u(1.0, 2.0)},
            {"trigger_gap_m", u(0.4, 0.8)},
            {"clearance_margin_m", u(0.05, 0.15)},
            {"max_deviation_m", u(0.15, 0.35)}};
  if (behaviour == "oblivious") return {{"lookahead_m", u(0.6, 1.5)}};
  if (behaviour == "social_force")
    return {{"relaxation_time_s", u(0.4, 0.7)},
            {"social_weight", u(1.5, 2.7)},
            {"robot_weight", u(3.0, 7.0)}};
  if (behaviour == "facilitating")
    return {{"trigger_ttc_s", u(4.0, 6.0)},
            {"trigger_distance_m", u(5.0, 8.0)},
            {"yield.offset_m", u(0.6, 1.0)}};
  if (behaviour == "late_facilitating")
    return {{"trigger_ttc_s", u(2.0, 3.5)},
            {"minimal.max_deviation_m", u(0.2, 0.35)},
            {"yield.offset_m", u(0.45, 0.75)}};
  if (behaviour == "responsive")
    return {{"reaction_time_median_s", u(0.7, 1.3)},
            {"repeat_increment_m", u(0.1, 0.3)},
            {"yield.offset_m", u(0.6, 0.9)}};
  return {};
}

inline std::string encounterName(std::size_t index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "pop_%04zu", index + 1);
  return buf;
}

/// Whether `name` is one of behaviourNames().
inline bool isBehaviourName(const std::string& name) {
  const auto& names = behaviourNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// The variant of the draws that widen a head-on encounter to what found the freezing robot
/// (issue 44; widen() draws the robot's kinematics and the tracker before it): either a second
/// person abreast of the head-on one (a pair walking together: same behaviour, speed and params,
/// group 1) or a person ahead of the robot walking its way slower than it (the robot follows,
/// and passes where the corridor allows). From a stream of the encounter's own (seeded by its
/// seed), after every other draw: the rest of the encounter, and every other encounter, stay as
/// drawn.
inline void widenVariant(Encounter& e, const Ranges& r, Rng& w) {
  const Layout& l = e.layout;
  const double v = w.unit();
  HumanSpec& h = e.humans.front();
  if (v < r.abreast_p) {
    const double spacing =
        quantize(w.uniform(r.abreast_spacing_min_m, r.abreast_spacing_max_m), 0.005);
    // Beside the head-on person on the side with room (the lanes round the pillar of open_wide
    // are narrower than a pair: its partner walks in the head-on person's own lane range).
    const double lo = l.lateral_min_y_m, hi = l.lateral_max_y_m;
    if (hi - lo < spacing) return;
    double y = h.start_y_m + (w.unit() < 0.5 ? spacing : -spacing);
    if (y > hi || y < lo) y = h.start_y_m - (y - h.start_y_m);
    if (y > hi || y < lo) {
      // Neither side fits as placed: the pair is centred on the head-on person's offset.
      const double mid = std::clamp(h.start_y_m, lo + spacing / 2.0, hi - spacing / 2.0);
      h.start_y_m = quantize(mid - spacing / 2.0, 0.005);
      h.goal_y_m = h.start_y_m;
      y = h.start_y_m + spacing;
    }
    HumanSpec x = h;
    x.id = static_cast<int>(e.humans.size()) + 1;
    x.start_y_m = quantize(y, 0.005);
    x.goal_y_m = x.start_y_m;
    x.start_x_m = quantize(h.start_x_m + w.uniform(0.0, 0.3), 0.005);
    h.group = 1;
    x.group = 1;
    e.humans.push_back(x);
    e.variant = "abreast";
  } else if (v < r.abreast_p + r.slower_ahead_p) {
    HumanSpec x;
    x.id = static_cast<int>(e.humans.size()) + 1;
    x.role = "same_way";
    x.behaviour = behaviourNames()[w.index(behaviourNames().size())];
    x.start_x_m =
        quantize(l.robot_start_x_m + w.uniform(r.slower_ahead_min_m, r.slower_ahead_max_m), 0.005);
    const auto& lane = l.extra_lanes_y_m.empty()
                           ? std::pair<double, double>{l.lateral_min_y_m, l.lateral_max_y_m}
                           : l.extra_lanes_y_m[w.index(l.extra_lanes_y_m.size())];
    x.start_y_m = quantize(std::clamp(l.centre_y_m + w.uniform(-r.extra_offset_m, r.extra_offset_m),
                                      lane.first, lane.second),
                           0.005);
    x.goal_x_m = l.same_way_goal_x_m;
    x.goal_y_m = x.start_y_m;
    x.speed_m_s = quantize(w.uniform(r.slower_speed_min_m_s, r.slower_speed_max_m_s), 0.01);
    x.velocity_noise_m_s = quantize(w.uniform(0.0, r.noise_max_m_s), 0.01);
    x.params = drawParams(x.behaviour, w);
    e.humans.push_back(x);
    e.variant = "slower_ahead";
  }
}

/// The widened draws (widenVariant), then a pause of one of the people: from the same stream,
/// after every earlier draw, so an encounter drawn before pauses existed keeps all it had.
inline void widen(Encounter& e, const Ranges& r) {
  Rng w(e.seed ^ 0x3D1DE11ULL);
  e.differential = w.unit() < r.differential_p;
  e.tracker_noise = w.unit() < r.tracker_noise_p;
  widenVariant(e, r, w);
  if (e.humans.empty() || !(w.unit() < r.pause_p)) return;
  HumanSpec& h = e.humans[w.index(e.humans.size())];
  const double path_m = std::hypot(h.goal_x_m - h.start_x_m, h.goal_y_m - h.start_y_m);
  const double after_m = w.uniform(r.pause_after_min_m, r.pause_after_max_m);
  h.pause_after_m = quantize(std::min(after_m, 0.5 * path_m), 0.1);
  h.pause_duration_s = quantize(w.uniform(r.pause_duration_min_s, r.pause_duration_max_s), 0.1);
}

/// The n encounters of `seed`. The head-on human's behaviour runs through the six in a seeded
/// order per block of six (every behaviour equally often); everything else is drawn.
///
/// head_on_behaviour (one of behaviourNames(), or empty): every head-on human gets this
/// behaviour instead, and everything else stays as the seed draws it without the option (layout,
/// positions, speeds, the other humans, the scenario seed): the population's stream still draws
/// the params of the behaviour the head-on human would have had, and the params of the one it is
/// given come from a stream of their own, seeded by the encounter's seed. A head-on human that
/// has that behaviour anyway keeps its own params, so the encounters the option does not change
/// are the same files byte for byte. Throws std::invalid_argument for an unknown behaviour.
inline std::vector<Encounter> generatePopulation(std::size_t n, std::uint64_t seed,
                                                 const Ranges& r = {},
                                                 const std::string& head_on_behaviour = "") {
  if (!head_on_behaviour.empty() && !isBehaviourName(head_on_behaviour))
    throw std::invalid_argument("no behaviour " + head_on_behaviour);
  std::vector<Layout> layouts = allLayouts();
  layouts.erase(std::remove_if(layouts.begin(), layouts.end(),
                               [&](const Layout& l) { return l.width_m > r.max_width_m + 1e-9; }),
                layouts.end());
  if (layouts.empty()) throw std::invalid_argument("no layout is that narrow");
  const auto& names = behaviourNames();
  Rng rng(seed ^ 0xC00B0A7ULL);
  std::vector<Encounter> out;
  std::array<std::size_t, 6> order{0, 1, 2, 3, 4, 5};
  for (std::size_t i = 0; i < n; ++i) {
    if (i % order.size() == 0) {
      for (std::size_t k = order.size() - 1; k > 0; --k)  // Fisher-Yates
        std::swap(order[k], order[rng.index(k + 1)]);
    }
    Encounter e;
    e.name = encounterName(i);
    e.seed = rng.next() >> 11;  // within the scenario's [0, 2^53]
    e.layout = layouts[rng.index(layouts.size())];
    const Layout& l = e.layout;
    auto clampY = [&](double y) { return std::clamp(y, l.lateral_min_y_m, l.lateral_max_y_m); };
    auto speed = [&] { return quantize(rng.uniform(r.speed_min_m_s, r.speed_max_m_s), 0.01); };
    auto noise = [&] { return quantize(rng.uniform(0.0, r.noise_max_m_s), 0.01); };
    auto extraY = [&] {
      if (l.extra_lanes_y_m.empty())
        return quantize(clampY(l.centre_y_m + rng.uniform(-r.extra_offset_m, r.extra_offset_m)),
                        0.005);
      const auto& lane = l.extra_lanes_y_m[rng.index(l.extra_lanes_y_m.size())];
      return quantize(rng.uniform(lane.first, lane.second), 0.005);
    };

    HumanSpec h;
    h.id = 1;
    h.role = "head_on";
    h.behaviour = names[order[i % order.size()]];
    h.start_x_m =
        quantize(l.robot_goal_x_m + rng.uniform(l.head_start_min_m, l.head_start_max_m), 0.005);
    h.start_y_m = quantize(
        clampY(l.centre_y_m + rng.uniform(-r.head_on_offset_m, r.head_on_offset_m)), 0.005);
    h.goal_x_m = l.head_goal_x_m;
    h.goal_y_m = h.start_y_m;
    h.speed_m_s = speed();
    h.velocity_noise_m_s = noise();
    h.params = drawParams(h.behaviour, rng);
    if (!head_on_behaviour.empty() && head_on_behaviour != h.behaviour) {
      Rng own(e.seed ^ 0x4EAD0BEA5ULL);
      h.behaviour = head_on_behaviour;
      h.params = drawParams(h.behaviour, own);
    }
    e.humans.push_back(h);

    const double p = rng.unit();
    const std::size_t count =
        p < r.three_humans_p ? 3 : (p < r.three_humans_p + r.two_humans_p ? 2 : 1);
    std::vector<std::string> roles;
    if (count == 3) roles = {"follower", "same_way"};
    if (count == 2) roles = {rng.unit() < 0.5 ? "follower" : "same_way"};
    for (const auto& role : roles) {
      HumanSpec x;
      x.id = static_cast<int>(e.humans.size()) + 1;
      x.role = role;
      x.behaviour = names[rng.index(names.size())];
      x.start_y_m = extraY();
      x.goal_y_m = x.start_y_m;
      if (role == "follower") {
        x.start_x_m =
            quantize(h.start_x_m + rng.uniform(r.follower_gap_min_m, r.follower_gap_max_m), 0.005);
        x.goal_x_m = l.follower_goal_x_m;
      } else {
        x.start_x_m = quantize(
            l.robot_start_x_m + rng.uniform(r.same_way_ahead_min_m, r.same_way_ahead_max_m), 0.005);
        x.goal_x_m = l.same_way_goal_x_m;
      }
      x.speed_m_s = speed();
      x.velocity_noise_m_s = noise();
      x.params = drawParams(x.behaviour, rng);
      e.humans.push_back(x);
    }
    widen(e, r);
    out.push_back(std::move(e));
  }
  return out;
}

// ---- Crowds (generate --crowd): several people at once, in four kinds of encounter.

/// The crowd kinds, in the order the generator cycles through them (a seeded order per block of
/// four, so each appears equally often): bidirectional flows in a corridor, a group walking
/// abreast towards the robot, people standing talking by a wall, a junction of junctions.pgm.
inline const std::array<const char*, 4>& crowdKindNames() {
  static const std::array<const char*, 4> k{"flows", "group_abreast", "standing_talk", "junction"};
  return k;
}

/// Widths of the synthetic corridors of the crowd kinds but the junction (from the paper's open
/// 6 m corridor down to 4 m, where a robot still passes a person on either side of it).
inline const std::vector<double>& crowdWidthsM() {
  static const std::vector<double> k{4.00, 5.00, 6.00};
  return k;
}

/// junctions.pgm around its junction (pixels of the map, config/maps/CREDIT.md): the robot's
/// 2.00 m corridor y 25.00-27.00 is crossed by a 1.50 m corridor x 23.50-25.00, whose branches
/// run north (y 27.25-39.70, a dead end) and south (free all the way down, across the 1.20 m
/// corridor at y 17.5-18.7 and the 1.50 m one at y 10.0-11.5).
struct JunctionGeometry {
  double branch_x0_m{23.5}, branch_x1_m{25.0};
  /// Where people crossing the robot's corridor walk to: the crossing corridor's centre line,
  /// the k-th one going that way goal_step_m short of the (k-1)-th (one after the other).
  double north_goal_y_m{38.6}, south_goal_y_m{10.75}, goal_step_m{1.0};
  double north_y0_m{27.25}, north_y1_m{39.7};
  double south_y0_m{10.0}, south_y1_m{24.75};
  double corridor_y0_m{25.0}, corridor_y1_m{27.0};
};

/// The junction layout: the robot crosses the junction, (13, 26) -> (33, 26); people turning
/// west walk to x 5 (the open area west of the blocks, behind the robot's start), east to x 38.6
/// (the open strip east of them, past the robot's goal): goals away from walls, which a social
/// force walker would not reach within its goal tolerance.
inline Layout junctionCrossLayout() {
  Layout l = junctionsCorridor();
  l.key = "junction_cross";
  l.robot_start_x_m = 13.0;
  l.robot_goal_x_m = 33.0;
  l.head_goal_x_m = 5.0;
  l.same_way_goal_x_m = 38.6;
  return l;
}

/// Ranges of the crowd kinds (docs/population.md "Crowds"). Speeds, noise and behaviour params
/// are Ranges' and drawParams'.
struct CrowdRanges {
  /// Centres at least this far apart at the start: two bodies (0.6 m) and 0.2 m.
  double min_start_gap_m{2 * kHumanRadiusM + 0.2};
  /// Nobody starts within this of the robot's start (centres).
  double robot_keep_out_m{2.5};
  /// Walkers' goals: at least this far apart (centres), and in a corridor at least this far
  /// from its walls (centre to the wall's face; the body 0.6 m off it): a social force walker
  /// stops short of a goal nearer a wall or another person by more than its goal tolerance.
  double goal_gap_m{1.0};
  double goal_wall_clearance_m{0.9};
  /// Corridors: people walking the robot's way walk to this x (the end wall's face at 33.9).
  double same_way_goal_x_m{32.0};
  // flows
  int flow_people_min{2}, flow_people_max{10};
  double flow_oncoming_p{0.6};
  double flow_oncoming_x_min_m{14.0};      ///< oncoming start x from here to the corridor's end - 1
  double flow_same_way_ahead_max_m{10.0};  ///< same-way start x robot start + [keep-out, this]
  // group_abreast
  int group_min{2}, group_max{3};
  double group_spacing_min_m{0.7}, group_spacing_max_m{0.9};
  double group_centre_offset_m{0.5};
  int group_extra_max{2};
  double group_follower_gap_min_m{2.0}, group_follower_gap_max_m{4.0};
  // standing_talk
  int talk_min{2}, talk_max{3};
  double talk_wall_gap_min_m{0.15}, talk_wall_gap_max_m{0.4};    ///< body to wall
  double talk_spacing_min_m{0.8}, talk_spacing_max_m{1.0};       ///< along the wall
  double talk_third_off_min_m{0.75}, talk_third_off_max_m{0.9};  ///< third one, off their line
  double talk_walker_p{0.5};
  // junction
  int junction_min{4}, junction_max{6};
  double junction_pair_spacing_m{0.7};
  /// People turning east (walking the robot's way) reach the junction within this many
  /// seconds, ahead of the robot (the robot reaches it after ~16 s).
  double junction_away_before_s{7.0};
};

namespace detail {

inline bool clearOf(const std::vector<HumanSpec>& placed, double x, double y, double gap) {
  for (const auto& p : placed)
    if (std::hypot(p.start_x_m - x, p.start_y_m - y) < gap - 1e-9) return false;
  return true;
}

/// A start drawn by `draw` (returns x, y; quantized) clear of every placed human by the gap;
/// tries a bounded number of times (the ranges leave room many times over). False: none found.
template <typename Draw>
bool placeClear(const std::vector<HumanSpec>& placed, double gap, Draw draw, double& x, double& y) {
  for (int attempt = 0; attempt < 200; ++attempt) {
    std::tie(x, y) = draw();
    if (clearOf(placed, x, y, gap)) return true;
  }
  return false;
}

/// Goals of walkers who would end up (nearly) on each other's goal are moved apart: a walker
/// cannot reach a goal another one stands on (a social force walker stops short of both), and
/// the run would end at its time limit. In id order, a goal within `gap` of an earlier one is
/// moved sideways by up to 1.5 m in steps of 0.5, further along the walker's last leg in steps of
/// `gap` (up to 4), or back along it (up to 3), to the first place clear of the earlier goals
/// inside `inside(x, y)`. No draw.
template <typename Inside>
void spreadGoals(std::vector<HumanSpec>& humans, double gap, Inside inside) {
  for (std::size_t k = 0; k < humans.size(); ++k) {
    HumanSpec& h = humans[k];
    if (h.speed_m_s <= 0.0) continue;
    auto clear = [&](double x, double y) {
      for (std::size_t j = 0; j < k; ++j)
        if (std::hypot(humans[j].goal_x_m - x, humans[j].goal_y_m - y) < gap - 1e-9) return false;
      return true;
    };
    if (clear(h.goal_x_m, h.goal_y_m)) continue;
    const double fx = h.via.empty() ? h.start_x_m : h.via.back()[0];
    const double fy = h.via.empty() ? h.start_y_m : h.via.back()[1];
    const double len = std::hypot(h.goal_x_m - fx, h.goal_y_m - fy);
    if (len <= 0.0) continue;
    const double ux = (h.goal_x_m - fx) / len, uy = (h.goal_y_m - fy) / len;
    bool moved = false;
    for (const int along : {0, 1, 2, 3, 4, -1, -2, -3}) {
      if (moved) break;
      for (const double side : {0.0, 0.5, -0.5, 1.0, -1.0, 1.5, -1.5}) {
        const double x = quantize(h.goal_x_m + along * gap * ux - side * uy, 0.005);
        const double y = quantize(h.goal_y_m + along * gap * uy + side * ux, 0.005);
        if (inside(x, y) && clear(x, y)) {
          h.goal_x_m = x;
          h.goal_y_m = y;
          moved = true;
          break;
        }
      }
    }
  }
}

}  // namespace detail

/// The n crowd encounters of `seed`. Every walker's behaviour is uniform over the six (a group
/// shares one, with one speed and one set of params); people standing are `minimal` at speed 0.
/// Roles: head_on (towards the robot), follower (behind a group, same direction), same_way
/// (ahead of the robot, its way), crossing (across its path, junction), standing.
inline std::vector<Encounter> generateCrowdPopulation(std::size_t n, std::uint64_t seed,
                                                      const Ranges& r = {},
                                                      const CrowdRanges& c = {}) {
  const auto& names = behaviourNames();
  const auto& kinds = crowdKindNames();
  const JunctionGeometry jg;
  Rng rng(seed ^ 0xC20DD5ULL);
  std::vector<Encounter> out;
  std::array<std::size_t, 4> order{0, 1, 2, 3};
  for (std::size_t i = 0; i < n; ++i) {
    if (i % order.size() == 0) {
      for (std::size_t k = order.size() - 1; k > 0; --k)  // Fisher-Yates
        std::swap(order[k], order[rng.index(k + 1)]);
    }
    Encounter e;
    e.name = encounterName(i);
    e.seed = rng.next() >> 11;
    e.kind = kinds[order[i % order.size()]];
    const bool junction = e.kind == "junction";
    e.layout = junction ? junctionCrossLayout()
                        : syntheticCorridor(crowdWidthsM()[rng.index(crowdWidthsM().size())]);
    const Layout& l = e.layout;
    auto q = [](double v) { return quantize(v, 0.005); };
    auto speed = [&] { return quantize(rng.uniform(r.speed_min_m_s, r.speed_max_m_s), 0.01); };
    auto noise = [&] { return quantize(rng.uniform(0.0, r.noise_max_m_s), 0.01); };
    auto laneY = [&] { return q(rng.uniform(l.lateral_min_y_m, l.lateral_max_y_m)); };
    // A corridor walker's goal: its lane, kept goal_wall_clearance_m from the walls.
    const double goal_y0 = c.goal_wall_clearance_m, goal_y1 = l.width_m - c.goal_wall_clearance_m;
    auto goalY = [&](double y) { return q(std::clamp(y, goal_y0, goal_y1)); };
    auto count = [&](int lo, int hi) {
      return lo + static_cast<int>(rng.index(static_cast<std::size_t>(hi - lo) + 1));
    };
    auto walker = [&](const std::string& role) {
      HumanSpec h;
      h.id = static_cast<int>(e.humans.size()) + 1;
      h.role = role;
      h.behaviour = names[rng.index(names.size())];
      h.speed_m_s = speed();
      h.velocity_noise_m_s = noise();
      h.params = drawParams(h.behaviour, rng);
      return h;
    };
    // Oncoming: towards the robot, to behind its start; same way: ahead of it, beyond its goal.
    auto addOncoming = [&](double x_min, double x_max, const std::string& role) {
      HumanSpec h = walker(role);
      if (!detail::placeClear(
              e.humans, c.min_start_gap_m,
              [&] { return std::pair(q(rng.uniform(x_min, x_max)), laneY()); }, h.start_x_m,
              h.start_y_m))
        return;
      h.goal_x_m = l.head_goal_x_m;
      h.goal_y_m = goalY(h.start_y_m);
      e.humans.push_back(h);
    };
    auto addSameWay = [&] {
      HumanSpec h = walker("same_way");
      const double x0 = l.robot_start_x_m + c.robot_keep_out_m;
      if (!detail::placeClear(
              e.humans, c.min_start_gap_m,
              [&] {
                return std::pair(
                    q(rng.uniform(x0, l.robot_start_x_m + c.flow_same_way_ahead_max_m)), laneY());
              },
              h.start_x_m, h.start_y_m))
        return;
      h.goal_x_m = c.same_way_goal_x_m;
      h.goal_y_m = goalY(h.start_y_m);
      e.humans.push_back(h);
    };

    if (e.kind == "flows") {
      const int people = count(c.flow_people_min, c.flow_people_max);
      for (int k = 0; k < people; ++k) {
        // Both ways: the first comes towards the robot, the second walks its way.
        const bool oncoming = k == 0 || (k > 1 && rng.unit() < c.flow_oncoming_p);
        if (oncoming)
          addOncoming(c.flow_oncoming_x_min_m, l.wall_x1_m - 1.0, "head_on");
        else
          addSameWay();
      }
    } else if (e.kind == "group_abreast") {
      const int size = count(c.group_min, c.group_max);
      const double spacing = q(rng.uniform(c.group_spacing_min_m, c.group_spacing_max_m));
      const double span = spacing * (size - 1);
      const double centre =
          std::clamp(l.centre_y_m + rng.uniform(-c.group_centre_offset_m, c.group_centre_offset_m),
                     l.lateral_min_y_m + span / 2, l.lateral_max_y_m - span / 2);
      const double x = q(l.robot_goal_x_m + rng.uniform(l.head_start_min_m, l.head_start_max_m));
      const HumanSpec first = walker("head_on");  // behaviour, speed, noise, params of them all
      for (int k = 0; k < size; ++k) {
        HumanSpec h = first;
        h.id = static_cast<int>(e.humans.size()) + 1;
        h.group = 1;
        h.start_x_m = x;
        h.start_y_m = q(centre - span / 2 + spacing * k);
        h.goal_x_m = l.head_goal_x_m;
        h.goal_y_m = goalY(h.start_y_m);
        e.humans.push_back(h);
      }
      const int extra = count(0, c.group_extra_max);
      for (int k = 0; k < extra; ++k) {
        if (rng.unit() < 0.5)
          addOncoming(x + c.group_follower_gap_min_m, x + c.group_follower_gap_max_m, "follower");
        else
          addSameWay();
      }
    } else if (e.kind == "standing_talk") {
      const int size = count(c.talk_min, c.talk_max);
      const bool upper = rng.unit() < 0.5;
      const double off = kHumanRadiusM + rng.uniform(c.talk_wall_gap_min_m, c.talk_wall_gap_max_m);
      const double y = q(upper ? l.width_m - off : off);
      const double x0 = q(rng.uniform(l.robot_start_x_m + 7.0, l.robot_goal_x_m - 5.0));
      const double spacing = q(rng.uniform(c.talk_spacing_min_m, c.talk_spacing_max_m));
      const double third_off = q(rng.uniform(c.talk_third_off_min_m, c.talk_third_off_max_m));
      for (int k = 0; k < size; ++k) {
        HumanSpec h;
        h.id = k + 1;
        h.role = "standing";
        h.behaviour = "minimal";
        h.speed_m_s = 0.0;
        h.group = 1;
        if (k < 2) {  // the two along the wall face each other
          h.start_x_m = q(x0 + spacing * k);
          h.start_y_m = y;
          h.start_theta = k == 0 ? "0.0" : "3.14159";
        } else {  // the third faces them and the wall
          h.start_x_m = q(x0 + spacing / 2);
          h.start_y_m = q(upper ? y - third_off : y + third_off);
          h.start_theta = upper ? "1.5708" : "-1.5708";
        }
        h.goal_x_m = h.start_x_m;
        h.goal_y_m = h.start_y_m;
        e.humans.push_back(h);
      }
      if (rng.unit() < c.talk_walker_p)
        addOncoming(l.robot_goal_x_m + l.head_start_min_m, l.robot_goal_x_m + l.head_start_max_m,
                    "head_on");
    } else {  // junction
      const int people = count(c.junction_min, c.junction_max);
      const double bx0 = jg.branch_x0_m + kHumanRadiusM + kStartMarginM;
      const double bx1 = jg.branch_x1_m - kHumanRadiusM - kStartMarginM;
      const double north_min = jg.north_y0_m + 0.75, north_max = jg.north_y1_m - 1.2;
      // From 2 m (north 2.75 m) to ~14 m off the robot's line: at 0.8-1.3 m/s they reach the
      // junction from 1.5 to 17 s, around the robot's ~16 s.
      const double south_min = jg.south_y0_m + 2.0, south_max = jg.south_y1_m - 0.75;
      // dest: 0 across the robot's path (the other branch), 1 west (towards the robot), 2 east
      // (its way: only people reaching the junction well ahead of it, else they would walk up
      // behind the robot at its goal in the 2 m corridor).
      int to_north = 0, to_south = 0;
      auto route = [&](HumanSpec& h, bool north, int dest) {
        const double lane = laneY();
        if (dest == 0) {
          h.role = "crossing";
          h.goal_x_m = (jg.branch_x0_m + jg.branch_x1_m) / 2;
          h.goal_y_m = north ? jg.south_goal_y_m - jg.goal_step_m * to_south++
                             : jg.north_goal_y_m - jg.goal_step_m * to_north++;
        } else {
          h.role = dest == 1 ? "head_on" : "same_way";
          h.via.push_back({h.start_x_m, lane});
          h.goal_x_m = dest == 1 ? l.head_goal_x_m : l.same_way_goal_x_m;
          h.goal_y_m = lane;
        }
        h.start_theta = north ? "-1.5708" : "1.5708";
      };
      auto startY = [&](bool north, int dest, double v) {
        double lo = north ? north_min : south_min, hi = north ? north_max : south_max;
        if (dest == 2) {  // within junction_away_before_s of the corridor's centre line
          const double reach = v * c.junction_away_before_s;
          if (north)
            hi = std::max(lo, std::min(hi, l.centre_y_m + reach));
          else
            lo = std::min(hi, std::max(lo, l.centre_y_m - reach));
        }
        return q(rng.uniform(lo, hi));
      };
      {  // the pair, walking abreast (across, or towards the robot)
        const bool north = rng.unit() < 0.5;
        const int dest = static_cast<int>(rng.index(2));
        HumanSpec first = walker("");
        first.start_y_m = startY(north, dest, first.speed_m_s);
        const double lane_in = laneY();
        for (int k = 0; k < 2; ++k) {
          HumanSpec h = first;
          h.id = k + 1;
          h.group = 1;
          h.start_x_m =
              q(bx0 + (bx1 - bx0 - c.junction_pair_spacing_m) / 2 + c.junction_pair_spacing_m * k);
          route(h, north, dest);
          if (dest == 1) {  // abreast in the corridor too: the inside of the turn nearer it
            const double half = c.junction_pair_spacing_m / 2;
            const double mid =
                std::clamp(lane_in, l.lateral_min_y_m + half, l.lateral_max_y_m - half);
            // The western one is on the inside of the turn: north of the other coming from
            // the north (a right turn), south of it coming from the south.
            const bool inside = k == 0;
            const double y = north == inside ? mid + half : mid - half;
            h.via[0][1] = q(y);
            h.goal_y_m = q(y);
          }
          e.humans.push_back(h);
        }
      }
      for (int k = 2; k < people; ++k) {
        // At least one across the robot's path and one walking away; then any of the three.
        const int dest = k == 2 ? 0 : (k == 3 ? 2 : static_cast<int>(rng.index(3)));
        HumanSpec h = walker("");
        const bool north = rng.unit() < 0.5;
        if (!detail::placeClear(
                e.humans, c.min_start_gap_m,
                [&] {
                  const double x = q(rng.uniform(bx0, bx1));
                  return std::pair(x, startY(north, dest, h.speed_m_s));
                },
                h.start_x_m, h.start_y_m))
          continue;
        route(h, north, dest);
        e.humans.push_back(h);
      }
    }
    for (std::size_t k = 0; k < e.humans.size(); ++k) e.humans[k].id = static_cast<int>(k) + 1;
    detail::spreadGoals(e.humans, c.goal_gap_m, [&](double x, double y) {
      // Never on the robot's way: behind its start or beyond its goal.
      const bool off_way = x <= l.robot_start_x_m - 0.5 || x >= l.robot_goal_x_m + 1.5;
      if (!junction)
        return off_way && y >= goal_y0 - 1e-9 && y <= goal_y1 + 1e-9 &&
               x >= l.wall_x0_m + 0.1 + c.goal_wall_clearance_m &&
               x <= l.wall_x1_m - 0.1 - c.goal_wall_clearance_m;
      // At the junction: in the open areas west of the blocks (x 0.3-6.85) and east of them
      // (x 37.5-39.7) round the robot's corridor's lanes, in those lanes, or on the crossing
      // corridor's centre line.
      const bool open = (x >= 1.2 && x <= 6.0) || (x >= 38.3 && x <= 38.8);
      const bool lane =
          off_way && x >= 1.2 && x <= 38.8 &&
          (open ? y >= l.centre_y_m - 1.6 && y <= l.centre_y_m + 1.6
                : y >= l.lateral_min_y_m + 0.2 - 1e-9 && y <= l.lateral_max_y_m - 0.2 + 1e-9);
      const bool branch = std::abs(x - (jg.branch_x0_m + jg.branch_x1_m) / 2) < 1e-9;
      return lane || branch;
    });
    out.push_back(std::move(e));
  }
  return out;
}

/// Flow mapping of params, "group.key" entries nested under their group in first-seen order.
inline std::string paramsYaml(const std::vector<std::pair<std::string, double>>& params) {
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, double>>>> groups;
  std::vector<std::pair<std::string, double>> top;
  std::vector<std::string> order;  // "k:" top-level key, "g:" group
  for (const auto& [key, v] : params) {
    const auto dot = key.find('.');
    if (dot == std::string::npos) {
      top.emplace_back(key, v);
      order.push_back("k:" + key);
      continue;
    }
    const std::string g = key.substr(0, dot);
    auto it = std::find_if(groups.begin(), groups.end(), [&](auto& x) { return x.first == g; });
    if (it == groups.end()) {
      groups.push_back({g, {}});
      order.push_back("g:" + g);
      it = groups.end() - 1;
    }
    it->second.emplace_back(key.substr(dot + 1), v);
  }
  std::string s = "{";
  bool first = true;
  for (const auto& o : order) {
    if (!first) s += ", ";
    first = false;
    const std::string name = o.substr(2);
    if (o[0] == 'k') {
      for (const auto& [k, v] : top)
        if (k == name) s += k + ": " + fmt("%.2f", v);
    } else {
      for (const auto& [g, kv] : groups) {
        if (g != name) continue;
        s += g + ": {";
        for (std::size_t j = 0; j < kv.size(); ++j)
          s += (j ? ", " : "") + kv[j].first + ": " + fmt("%.2f", kv[j].second);
        s += "}";
      }
    }
  }
  return s + "}";
}

inline std::string pose(double x, double y, const char* theta = nullptr) {
  std::string s = "{x_m: " + fmt("%.3f", x) + ", y_m: " + fmt("%.3f", y);
  if (theta) s += std::string(", theta_rad: ") + theta;
  return s + "}";
}

/// Scenario YAML of an encounter (with_humans false: the same run without anyone, the baseline
/// of the time to goal). Map files are referenced as ../maps/<file>, beside the scenarios folder.
inline std::string scenarioYaml(const Encounter& e, bool with_humans = true,
                                const std::string& name_override = "") {
  const Layout& l = e.layout;
  std::string y;
  y += "# Generated by coopnav_population (tools/population): layout " + l.key + ", " +
       std::to_string(with_humans ? e.humans.size() : 0) + " human(s)" +
       (e.kind.empty() || !with_humans ? std::string() : ", crowd " + e.kind) + ".\n";
  y += "name: " + (name_override.empty() ? e.name : name_override) + "\n";
  y += "seed: " + std::to_string(with_humans ? e.seed : 1) + "\n";
  y += "time_limit_s: 90.0\n";
  y += "map:\n";
  if (!l.map_file.empty()) {
    y += "  file: ../maps/" + l.map_file + "\n";
    if (!l.goal_regions_m.empty()) y += "  goal_regions:\n";
    for (const auto& r : l.goal_regions_m)
      y += "    - {x0_m: " + fmt("%.2f", r[0]) + ", y0_m: " + fmt("%.2f", r[1]) +
           ", x1_m: " + fmt("%.2f", r[2]) + ", y1_m: " + fmt("%.2f", r[3]) + "}\n";
  } else {
    const std::string x0 = fmt("%.2f", l.wall_x0_m), x1 = fmt("%.2f", l.wall_x1_m);
    const std::string lo = "-0.10", hi = fmt("%.2f", l.width_m + 0.1);
    y += "  resolution_m: 0.05\n  walls:\n";
    y += "    - {x0_m: " + x0 + ", y0_m: " + lo + ", x1_m: " + x1 + ", y1_m: " + lo +
         ", thickness_m: 0.2}\n";
    y += "    - {x0_m: " + x0 + ", y0_m: " + hi + ", x1_m: " + x1 + ", y1_m: " + hi +
         ", thickness_m: 0.2}\n";
    y += "    - {x0_m: " + x0 + ", y0_m: " + lo + ", x1_m: " + x0 + ", y1_m: " + hi +
         ", thickness_m: 0.2}\n";
    y += "    - {x0_m: " + x1 + ", y0_m: " + lo + ", x1_m: " + x1 + ", y1_m: " + hi +
         ", thickness_m: 0.2}\n";
  }
  y += "rates: {physics_hz: 20, publish_hz: 10}\n";
  y += "lockstep:\n  enabled: true\n";
  y += "  participants: [band_source, situation_assessor, path_assessor, dialogue_manager]\n";
  y += "  step_timeout_s: 20\n";
  y += "robot:\n";
  y += "  start: " + pose(l.robot_start_x_m, l.centre_y_m, "0.0") + "\n";
  y += "  goal: " + pose(l.robot_goal_x_m, l.centre_y_m, "0.0") + "\n";
  y += std::string("  kinematics: ") + (e.differential ? "differential" : "holonomic") + "\n";
  y += "  limits: {max_forward_m_s: 0.7, max_lateral_m_s: 0.7}\n";
  if (with_humans && e.tracker_noise) {
    // scripts/population.sh --tracker-noise's model, for this encounter only.
    y += "tracker: {position_sigma_m: 0.05, miss_probability: 0.05, id_switches: 1}\n";
  }
  if (!with_humans || e.humans.empty()) {
    y += "humans: []\n";
    return y;
  }
  y += "humans:\n";
  for (const auto& h : e.humans) {
    const bool towards = h.goal_x_m < h.start_x_m;
    y += "  - id: " + std::to_string(h.id) + "  # " + h.role + "\n";
    const char* theta =
        h.start_theta.empty() ? (towards ? "3.14159" : "0.0") : h.start_theta.c_str();
    y += "    start: " + pose(h.start_x_m, h.start_y_m, theta) + "\n";
    if (!h.via.empty()) {
      y += "    via: [";
      for (std::size_t j = 0; j < h.via.size(); ++j)
        y += (j ? ", " : "") + pose(h.via[j][0], h.via[j][1]);
      y += "]\n";
    }
    y += "    goal: " + pose(h.goal_x_m, h.goal_y_m) + "\n";
    y += "    behaviour: " + h.behaviour + "\n";
    y += "    speed_m_s: " + fmt("%.2f", h.speed_m_s) + "\n";
    y += "    velocity_noise_m_s: " + fmt("%.2f", h.velocity_noise_m_s) + "\n";
    if (!h.params.empty()) y += "    params: " + paramsYaml(h.params) + "\n";
    if (h.pause_duration_s > 0.0)
      y += "    pause: {after_m: " + fmt("%.1f", h.pause_after_m) +
           ", duration_s: " + fmt("%.1f", h.pause_duration_s) + "}\n";
  }
  return y;
}

/// Name of the run without humans of a layout.
inline std::string baselineName(const Layout& l) {
  std::string s = "base_" + l.key;
  std::replace(s.begin(), s.end(), '.', '_');
  return s;
}

/// Name of the run without humans of an encounter: its layout's, and a differential robot's
/// own (it turns where a holonomic one slides: another time to goal).
inline std::string baselineName(const Encounter& e) {
  return baselineName(e.layout) + (e.differential ? "_differential" : "");
}

}  // namespace coopnav::population
