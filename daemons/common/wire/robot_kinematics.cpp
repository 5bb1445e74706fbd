#include "wire/robot_kinematics.hpp"

namespace coopnav {
namespace {
constexpr const char* kTag = "robot kinematics ";
const char* name(bool holonomic) { return holonomic ? "holonomic" : "differential"; }
}  // namespace

std::string robotKinematicsDetail(bool holonomic) { return std::string(kTag) + name(holonomic); }

std::optional<bool> holonomicFromStatusDetail(const std::string& detail) {
  const std::size_t at = detail.find(kTag);
  if (at == std::string::npos) return std::nullopt;
  const std::string rest = detail.substr(at + std::string(kTag).size());
  // The word must end there: "holonomicity" is no announcement.
  auto is = [&](const std::string& word) {
    return rest.compare(0, word.size(), word) == 0 &&
           (rest.size() == word.size() || rest[word.size()] == ';' || rest[word.size()] == ' ' ||
            rest[word.size()] == ',');
  };
  if (is("holonomic")) return true;
  if (is("differential")) return false;
  return std::nullopt;
}

std::string robotKinematicsMismatch(bool scenario_holonomic, bool band_source_holonomic) {
  return std::string("robot kinematics mismatch: the scenario's robot.kinematics is ") +
         name(scenario_holonomic) + " but the band source plans with planner.robot.holonomic: " +
         (band_source_holonomic ? "true" : "false") +
         " (config/band_source.yaml); make them agree (e.g. --set planner.robot.holonomic=" +
         (scenario_holonomic ? "true" : "false") + " for the band source)";
}

}  // namespace coopnav
