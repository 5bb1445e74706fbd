#pragma once
/// @file The forecast profile file (config/path_assessor_forecast.yaml): a fitted
/// assessment::ForecastModel (lib assessment/forecast.hpp) as YAML. Written by `coopnav_ctl
/// forecast --write-profile`, read by the same tool and by the path assessor (its
/// `forecast_profile` key). A model file, not a daemon config: no visit(), no defaults; every
/// field must be there, finite, every scale > 0.

#include <string>

#include "coopnav/assessment/forecast.hpp"

namespace coopnav {

/// The profile file of a model (every number to 17 significant digits: it reads back exactly).
std::string forecastProfileYaml(const assessment::ForecastModel& m);

/// Reads a profile; throws std::runtime_error("<path>: <reason>") on a missing or unreadable file,
/// a missing key, a value that is not a finite number, or a scale that is not > 0.
assessment::ForecastModel loadForecastProfile(const std::string& path);

}  // namespace coopnav
