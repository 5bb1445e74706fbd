#include "profiles/forecast_profile.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace coopnav {
namespace {

std::string exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

std::string forecastProfileYaml(const assessment::ForecastModel& m) {
  std::ostringstream o;
  o << "# The forecast profile: p_contributing, the probability that the human WILL have stepped\n"
       "# >= 0.3 m away from the robot by the crossing, from its track so far (lib assessment/\n"
       "# forecast.hpp: logistic regression on standardised features, fitted by IRLS with an L2\n"
       "# penalty). Written by `coopnav_ctl forecast test/data/pedestrians/headon_pairs.json\n"
       "# --write-profile config/path_assessor_forecast.yaml` (fit on all 172 real head-on pairs;\n"
       "# tools/ctl/README.md, \"Judgement in time\"; "
       "test/unit/tools/pedestrians_forecast_test.cpp\n"
       "# checks that this file is that fit). p = 1 / (1 + exp(-(bias + sum_i weight_i *\n"
       "# (x_i - mean_i) / scale_i))). A model file, not a daemon config (no -c): named by the\n"
       "# path assessor's `forecast_profile` key, read by daemons/common/profiles.\n";
  o << "# L2 penalty the weights were fitted with (on standardised features; the bias is free).\n";
  o << "l2: " << exact(m.l2) << "\n";
  o << "# Intercept (log-odds at the mean features).\n";
  o << "bias: " << exact(m.bias) << "\n";
  o << "# Per feature (forecast.hpp, ForecastFeatures): mean and scale (population standard\n"
       "# deviation) on the fitted samples, and the weight on (x - mean) / scale.\n";
  o << "features:\n";
  const auto& names = assessment::forecastFeatureNames();
  for (std::size_t i = 0; i < assessment::kForecastFeatureCount; ++i) {
    o << "  " << names[i] << ":\n";
    o << "    mean: " << exact(m.mean[i]) << "\n";
    o << "    scale: " << exact(m.scale[i]) << "\n";
    o << "    weight: " << exact(m.weight[i]) << "\n";
  }
  return o.str();
}

assessment::ForecastModel loadForecastProfile(const std::string& path) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  if (!doc.IsMap()) throw std::runtime_error(path + ": not a YAML map");
  const auto number = [&](const YAML::Node& n, const std::string& key) {
    if (!n || !n.IsScalar()) throw std::runtime_error(path + ": missing " + key);
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const std::exception&) {
      throw std::runtime_error(path + ": " + key + " is not a number");
    }
    if (!std::isfinite(v)) throw std::runtime_error(path + ": " + key + " is not finite");
    return v;
  };
  assessment::ForecastModel m;
  m.l2 = number(doc["l2"], "l2");
  m.bias = number(doc["bias"], "bias");
  const auto& names = assessment::forecastFeatureNames();
  const YAML::Node f = doc["features"];
  if (!f || !f.IsMap()) throw std::runtime_error(path + ": missing features");
  for (std::size_t i = 0; i < assessment::kForecastFeatureCount; ++i) {
    const std::string k = std::string("features.") + names[i];
    const YAML::Node n = f[names[i]];
    if (!n || !n.IsMap()) throw std::runtime_error(path + ": missing " + k);
    m.mean[i] = number(n["mean"], k + ".mean");
    m.scale[i] = number(n["scale"], k + ".scale");
    if (!(m.scale[i] > 0.0)) throw std::runtime_error(path + ": " + k + ".scale must be > 0");
    m.weight[i] = number(n["weight"], k + ".weight");
  }
  return m;
}

}  // namespace coopnav
