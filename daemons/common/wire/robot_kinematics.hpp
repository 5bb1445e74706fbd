#pragma once
/// @file The robot's kinematics as the band source announces it in its daemon_status_t detail,
/// so that world_sim can refuse a scenario whose robot moves otherwise than the one the band
/// source plans, guards and makes room for (docs/scenario-format.md `robot.kinematics`; band
/// source `planner.robot.holonomic`). One kinematics, declared in the band source's config: the
/// simulator checks its scenario against it instead of silently running another robot (a
/// holonomic plan on a differential body never swerves; its vy is dropped).

#include <optional>
#include <string>

namespace coopnav {

/// "robot kinematics holonomic" or "robot kinematics differential": appended to the band
/// source's status detail (after "; ").
std::string robotKinematicsDetail(bool holonomic);

/// The kinematics a status detail announces: true holonomic, false differential, nullopt when
/// the detail holds no announcement (another daemon, or a degraded band source's reason).
std::optional<bool> holonomicFromStatusDetail(const std::string& detail);

/// The error of a mismatch, naming both settings, e.g. "the scenario's robot.kinematics is
/// differential but the band source plans with planner.robot.holonomic: true (...)".
std::string robotKinematicsMismatch(bool scenario_holonomic, bool band_source_holonomic);

}  // namespace coopnav
