#include "coopnav/band/band_config.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace coopnav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

class Checker {
 public:
  explicit Checker(std::vector<BandPlannerConfig::Error>* out) : out_(out) {}
  /// value must lie in [lo, hi] (open ends when lo_open / hi_open).
  void range(const std::string& key, double v, double lo, double hi, bool lo_open = false) {
    const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
    if (!ok) {
      std::string allowed = (lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + "]";
      out_->push_back({key, v, allowed});
    }
  }

 private:
  static std::string fmt(double v) {
    if (v == kInf) return "inf";
    std::string s = std::to_string(v);
    while (s.size() > 1 && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
  }
  std::vector<BandPlannerConfig::Error>* out_;
};

/// Checks each key against its range (BandPlannerConfig::forEachKey), nested keys as "a.b".
struct KeyChecker {
  Checker& c;
  std::vector<BandPlannerConfig::Error>& errors;
  std::string prefix;

  template <class T>
  void operator()(const char* key, const T& v, const KeyRange& r) const {
    c.range(prefix + key, static_cast<double>(v), r.lo, r.hi, r.lo_open);
  }
  void operator()(const char* key, const std::string& v, const KeyChoices& choices) const {
    if (std::find(choices.values.begin(), choices.values.end(), v) != choices.values.end()) return;
    std::string allowed;
    for (const auto& x : choices.values) allowed += (allowed.empty() ? "" : " | ") + x;
    errors.push_back({prefix + key, std::numeric_limits<double>::quiet_NaN(), allowed});
  }
  void operator()(const char* /*key*/, const bool& /*flag*/) const {}
  void operator()(const char* key, const AgentKinematics& k) const {
    AgentKinematics::forEachKey(k, KeyChecker{c, errors, prefix + key + "."});
  }
  void operator()(const char* key, const BandWeights& w) const {
    BandWeights::forEachKey(w, KeyChecker{c, errors, prefix + key + "."});
  }
};

}  // namespace

std::vector<BandPlannerConfig::Error> BandPlannerConfig::validate() const {
  std::vector<Error> errors;
  Checker c(&errors);
  forEachKey(*this, KeyChecker{c, errors, ""});
  return errors;
}

}  // namespace coopnav
