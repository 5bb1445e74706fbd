#include "coopnav/sim/recorded.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "coopnav/sim/behaviour.hpp"

namespace coopnav::sim {

namespace {

/// A recorded human faces where it first moves once it is this far from its start [m].
constexpr double kHeadingMinMove_m = 0.05;
/// Safety factor on the acceleration limit when correcting an error: leaves room for the
/// discrete step (as the body check's brake_fraction).
constexpr double kCorrectionBrakeFraction = 0.8;

/// The fields of a CSV row: split at commas and whitespace.
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (const char c : line) {
    if (c == ',' || c == ' ' || c == '\t' || c == '\r') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

/// [bytes] Of a bad row, what its error quotes: a row of a hostile file may be megabytes long.
constexpr std::size_t kQuotedRowBytes = 80;

/// `text` for an error message: its first kQuotedRowBytes bytes, control bytes and bytes above
/// 0x7E as \xNN (a file's text must not steer the terminal), and how long it was if cut.
std::string quoted(const std::string& text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  const std::size_t n = std::min(text.size(), kQuotedRowBytes);
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c > 0x7E) {
      out += "\\x";
      out += kHex[c >> 4U];
      out += kHex[c & 0xFU];
    } else {
      out += static_cast<char>(c);
    }
  }
  if (n < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

/// Parses a whole field as a finite double.
bool toNumber(const std::string& s, double& out) {
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(x)) return false;
  out = x;
  return true;
}

Eigen::Vector2d toWorld(const RecordedParams& p, double x_m, double y_m) {
  const double c = std::cos(p.transform.theta_rad);
  const double s = std::sin(p.transform.theta_rad);
  return {p.transform.x_m + c * x_m - s * y_m, p.transform.y_m + s * x_m + c * y_m};
}

/// Recording time played at sim time t_s.
double recordingTime(const RecordedParams& p, double t_s) {
  return p.track.front().t_s + (t_s - p.time_offset_s);
}

class RecordedBehaviour final : public HumanBehaviour {
 public:
  explicit RecordedBehaviour(const RecordedParams& p) : p_(p) {
    if (p_.track.empty()) throw std::invalid_argument("behaviour recorded needs a track");
  }
  Velocity2 desiredVelocity(const BehaviourContext& ctx) override {
    const Eigen::Vector2d now = recordedPosition(p_, ctx.t_s);
    const Eigen::Vector2d next = recordedPosition(p_, ctx.t_s + ctx.dt_s);
    const Eigen::Vector2d self = ctx.self->pose.position();
    // The track's own velocity over this step, plus the velocity that removes the error in one
    // step, the latter no faster than the acceleration limit can stop at the track (sqrt(2 a e)).
    const Eigen::Vector2d error = now - self;
    Eigen::Vector2d correction = error / ctx.dt_s;
    const double max_correction_m_s =
        std::sqrt(2.0 * kCorrectionBrakeFraction * ctx.max_acc_m_s2 * error.norm());
    if (correction.norm() > max_correction_m_s && correction.norm() > 0.0)
      correction *= max_correction_m_s / correction.norm();
    const Eigen::Vector2d v = (next - now) / ctx.dt_s + correction;
    const double t_rec = recordingTime(p_, ctx.t_s);
    mode_ = t_rec < p_.track.front().t_s ? "waiting"
                                         : (t_rec > p_.track.back().t_s ? "ended" : "replay");
    return {v.x(), v.y(), 0.0};
  }
  BehaviourStatus status() const override { return {mode_, 0.0}; }
  const char* name() const override { return "recorded"; }

 private:
  RecordedParams p_;
  std::string mode_{"waiting"};
};

}  // namespace

std::vector<TrackSample> parseTrackCsv(const std::string& text, const std::string& source) {
  std::vector<TrackSample> out;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  bool first_content = true;
  while (std::getline(in, line)) {
    ++line_no;
    const std::vector<std::string> f = fields(line);
    if (f.empty() || f.front().front() == '#') continue;
    double v[3] = {0.0, 0.0, 0.0};
    bool numeric = f.size() == 3;
    for (std::size_t i = 0; i < f.size() && i < 3; ++i) numeric = toNumber(f[i], v[i]) && numeric;
    const bool header = first_content && !toNumber(f.front(), v[0]);
    first_content = false;
    if (header) continue;
    const std::string at = source + ":" + std::to_string(line_no) + ": ";
    if (!numeric)
      throw TrackError(at +
                       "expected three finite numbers 't x y' (comma or space separated), "
                       "got '" +
                       quoted(line) + "'");
    if (!out.empty() && !(v[0] > out.back().t_s))
      throw TrackError(at + "time " + quoted(f[0]) + " is not after the previous row's");
    out.push_back({v[0], v[1], v[2]});
  }
  if (out.empty()) throw TrackError(source + ": no 't x y' rows");
  return out;
}

void checkTrack(const std::vector<TrackSample>& track, const std::string& source) {
  if (track.empty()) throw TrackError(source + ": the track has no samples");
  for (std::size_t i = 0; i < track.size(); ++i) {
    const TrackSample& s = track[i];
    const std::string at = source + ": sample " + std::to_string(i) + ": ";
    if (!std::isfinite(s.t_s) || !std::isfinite(s.x_m) || !std::isfinite(s.y_m))
      throw TrackError(at + "not a finite number");
    if (i > 0 && !(s.t_s > track[i - 1].t_s))
      throw TrackError(at + "time is not after the previous sample's");
  }
}

Eigen::Vector2d recordedPosition(const RecordedParams& p, double t_s) {
  const auto& tr = p.track;
  const double t = recordingTime(p, t_s);
  if (t <= tr.front().t_s) return toWorld(p, tr.front().x_m, tr.front().y_m);
  if (t >= tr.back().t_s) return toWorld(p, tr.back().x_m, tr.back().y_m);
  const auto it = std::upper_bound(tr.begin(), tr.end(), t,
                                   [](double tt, const TrackSample& s) { return tt < s.t_s; });
  const TrackSample& b = *it;
  const TrackSample& a = *(it - 1);
  const double f = (t - a.t_s) / (b.t_s - a.t_s);
  return toWorld(p, a.x_m + f * (b.x_m - a.x_m), a.y_m + f * (b.y_m - a.y_m));
}

double recordedEnd_s(const RecordedParams& p) {
  return p.time_offset_s + (p.track.back().t_s - p.track.front().t_s);
}

Pose2 recordedStart(const RecordedParams& p) {
  const Eigen::Vector2d start = recordedPosition(p, 0.0);
  double theta = p.transform.theta_rad;
  const double t0 = recordingTime(p, 0.0);
  for (const TrackSample& s : p.track) {
    if (s.t_s <= t0) continue;
    const Eigen::Vector2d d = toWorld(p, s.x_m, s.y_m) - start;
    if (d.norm() > kHeadingMinMove_m) {
      theta = std::atan2(d.y(), d.x());
      break;
    }
  }
  return {start.x(), start.y(), theta};
}

Pose2 recordedGoal(const RecordedParams& p) {
  const Eigen::Vector2d goal = toWorld(p, p.track.back().x_m, p.track.back().y_m);
  double theta = p.transform.theta_rad;
  for (auto it = p.track.rbegin(); it != p.track.rend(); ++it) {
    const Eigen::Vector2d d = goal - toWorld(p, it->x_m, it->y_m);
    if (d.norm() > kHeadingMinMove_m) {
      theta = std::atan2(d.y(), d.x());
      break;
    }
  }
  return {goal.x(), goal.y(), theta};
}

std::unique_ptr<HumanBehaviour> makeRecordedBehaviour(const RecordedParams& params) {
  return std::make_unique<RecordedBehaviour>(params);
}

}  // namespace coopnav::sim
