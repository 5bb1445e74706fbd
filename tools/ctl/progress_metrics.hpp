#pragma once
/// @file Progress of the robot in one recorded run, from the agent states and the robot's
/// commands alone (summary.json `progress`): stalled time and the longest mutual wait. Francis et
/// al., "Principles and Guidelines for Evaluating Social Robot Navigation Algorithms" (THRI 2025)
/// name them "stalled time" and "failure to progress"; a mutual wait is the freezing-robot
/// stand-off (Trautman & Krause 2010): robot and person both still, near each other, neither
/// going.

#include <cstdint>

#include "logfile/log_reader.hpp"

namespace coopnav::ctl {

/// The robot is stalled below this speed [m/s].
inline constexpr double kStalledSpeed_m_s = 0.05;
/// A person waits below this speed [m/s]: well under a walk (≥ 0.5 m/s), above the velocity
/// noise of a tracked person standing still.
inline constexpr double kHumanWaitingSpeed_m_s = 0.2;
/// Near enough to be waiting for each other [m], surface to surface: within the room a passage
/// is negotiated in (a corridor's width and a step), not someone standing far down the hall.
inline constexpr double kMutualWaitGap_m = 2.0;

struct ProgressMetrics {
  /// Time the robot was slower than kStalledSpeed_m_s while its command was neither "at the
  /// goal" nor a requested dock, hold or retreat [s].
  double stalled_s{0.0};
  /// The longest span in which the robot was stalled (any mode but at its goal) and a person
  /// within kMutualWaitGap_m was slower than kHumanWaitingSpeed_m_s [s], and when it began
  /// (NaN when none).
  double max_mutual_wait_s{0.0};
  double max_mutual_wait_start_s{0.0};
  std::int32_t max_mutual_wait_human{-1};
};

ProgressMetrics progressMetrics(const RunLog& run);

}  // namespace coopnav::ctl
