#include "svg_figures.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "coopnav/assessment/path_assessment.hpp"
#include "summary.hpp"
#include "transcript.hpp"

namespace coopnav::ctl {
namespace {

constexpr const char* kRobotColor = "#1f77b4";
constexpr const char* kHumanColors[] = {"#d62728", "#2ca02c", "#9467bd",
                                        "#ff7f0e", "#8c564b", "#e377c2"};
constexpr const char* kGuideColor = "#7f7f7f";

std::string humanColor(std::size_t index) {
  return kHumanColors[index % (sizeof kHumanColors / sizeof kHumanColors[0])];
}

std::string esc(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        // XML 1.0 has no control characters but tab/newline: a name from the bus may carry any.
        out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
    }
  }
  return out;
}

std::string px(double v) { return fixed(v, 2); }

// 1, 2 or 5 times a power of ten, giving about `target` intervals over `range`.
double niceStep(double range, int target) {
  const double raw = range / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * mag;
}

int decimalsFor(double step) {
  return step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
}

struct Bounds {
  double x0{std::numeric_limits<double>::infinity()};
  double x1{-std::numeric_limits<double>::infinity()};
  double y0{std::numeric_limits<double>::infinity()};
  double y1{-std::numeric_limits<double>::infinity()};
  void addX(double x) {
    if (!std::isfinite(x)) return;
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
  }
  void addY(double y) {
    if (!std::isfinite(y)) return;
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
};

bool finitePoint(const std::array<double, 2>& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]);
}

}  // namespace

std::string SvgPlot::render() const {
  Bounds b;
  for (const auto& s : series)
    for (const auto& p : s.points)
      if (finitePoint(p)) {
        b.addX(p[0]);
        b.addY(p[1]);
      }
  for (const auto& m : markers)
    if (std::isfinite(m.x) && std::isfinite(m.y)) {
      b.addX(m.x);
      b.addY(m.y);
    }
  for (const auto& g : guides) (g.vertical ? b.addX(g.value) : b.addY(g.value));
  if (!(b.x0 <= b.x1)) b.x0 = 0.0, b.x1 = 1.0;
  if (!(b.y0 <= b.y1)) b.y0 = 0.0, b.y1 = 1.0;
  if (b.x1 - b.x0 < 1e-9) b.x0 -= 0.5, b.x1 += 0.5;
  if (b.y1 - b.y0 < 1e-9) b.y0 -= 0.5, b.y1 += 0.5;
  const double pad_x = 0.04 * (b.x1 - b.x0);
  const double pad_y = 0.06 * (b.y1 - b.y0);
  double x0 = b.x0 - pad_x, x1 = b.x1 + pad_x, y0 = b.y0 - pad_y, y1 = b.y1 + pad_y;

  // Legend entries: labelled series, then each distinct marker label.
  struct LegendItem {
    std::string label, color;
    bool dashed;
    int kind;  // 0 line, 1 circle, 2 square
  };
  std::vector<LegendItem> legend;
  for (const auto& s : series)
    if (!s.label.empty()) legend.push_back({s.label, s.color, s.dashed, 0});
  for (const auto& m : markers) {
    if (m.label.empty()) continue;
    const bool seen = std::any_of(legend.begin(), legend.end(),
                                  [&](const LegendItem& l) { return l.label == m.label; });
    if (!seen)
      legend.push_back({m.label, m.color, false, m.shape == Marker::Shape::kCircle ? 1 : 2});
  }

  const double width = 900.0, left = 70.0, right = 30.0, bottom = 55.0;
  std::vector<std::array<double, 2>> legend_pos;
  int rows = legend.empty() ? 0 : 1;
  double cx = left;
  for (const auto& item : legend) {
    const double w = 34.0 + 7.0 * static_cast<double>(item.label.size()) + 18.0;
    if (cx + w > width - right && cx > left) {
      ++rows;
      cx = left;
    }
    legend_pos.push_back({cx, 36.0 + 18.0 * (rows - 1)});
    cx += w;
  }
  const double top = 44.0 + 18.0 * rows;

  double plot_w = width - left - right;
  double plot_h = 380.0;
  if (equal_aspect) {
    double scale = plot_w / (x1 - x0);
    plot_h = (y1 - y0) * scale;
    if (plot_h > 600.0) {
      scale = 600.0 / (y1 - y0);
      plot_h = 600.0;
      plot_w = (x1 - x0) * scale;
    } else if (plot_h < 160.0) {
      const double extra = (160.0 / scale - (y1 - y0)) / 2.0;
      y0 -= extra;
      y1 += extra;
      plot_h = 160.0;
    }
  }
  const double height = top + plot_h + bottom;
  auto mx = [&](double x) { return left + (x - x0) / (x1 - x0) * plot_w; };
  auto my = [&](double y) { return top + (y1 - y) / (y1 - y0) * plot_h; };

  std::string o;
  o += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  o += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + px(width) + "\" height=\"" +
       px(height) + "\" viewBox=\"0 0 " + px(width) + " " + px(height) +
       "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  o += "<rect x=\"0\" y=\"0\" width=\"" + px(width) + "\" height=\"" + px(height) +
       "\" fill=\"white\"/>\n";
  o += "<text x=\"" + px(width / 2) + "\" y=\"20\" text-anchor=\"middle\" font-size=\"15\">" +
       esc(title) + "</text>\n";

  // Grid and tick labels.
  const double sx = niceStep(x1 - x0, 10), sy = niceStep(y1 - y0, equal_aspect ? 6 : 8);
  for (long k = static_cast<long>(std::ceil(x0 / sx)); k * sx <= x1; ++k) {
    const double v = k * sx, p = mx(v);
    o += "<line x1=\"" + px(p) + "\" y1=\"" + px(top) + "\" x2=\"" + px(p) + "\" y2=\"" +
         px(top + plot_h) + "\" stroke=\"#e6e6e6\"/>\n";
    o += "<text x=\"" + px(p) + "\" y=\"" + px(top + plot_h + 16) + "\" text-anchor=\"middle\">" +
         fixed(v, decimalsFor(sx)) + "</text>\n";
  }
  for (long k = static_cast<long>(std::ceil(y0 / sy)); k * sy <= y1; ++k) {
    const double v = k * sy, p = my(v);
    o += "<line x1=\"" + px(left) + "\" y1=\"" + px(p) + "\" x2=\"" + px(left + plot_w) +
         "\" y2=\"" + px(p) + "\" stroke=\"#e6e6e6\"/>\n";
    o += "<text x=\"" + px(left - 6) + "\" y=\"" + px(p + 4) + "\" text-anchor=\"end\">" +
         fixed(v, decimalsFor(sy)) + "</text>\n";
  }
  o += "<rect x=\"" + px(left) + "\" y=\"" + px(top) + "\" width=\"" + px(plot_w) + "\" height=\"" +
       px(plot_h) + "\" fill=\"none\" stroke=\"black\"/>\n";
  o += "<text x=\"" + px(left + plot_w / 2) + "\" y=\"" + px(height - 14) +
       "\" text-anchor=\"middle\">" + esc(x_label) + "</text>\n";
  o += "<text x=\"18\" y=\"" + px(top + plot_h / 2) +
       "\" text-anchor=\"middle\" transform=\"rotate(-90 18 " + px(top + plot_h / 2) + ")\">" +
       esc(y_label) + "</text>\n";

  o += "<clipPath id=\"plot-area\"><rect x=\"" + px(left) + "\" y=\"" + px(top) + "\" width=\"" +
       px(plot_w) + "\" height=\"" + px(plot_h) + "\"/></clipPath>\n";
  o += "<g clip-path=\"url(#plot-area)\">\n";
  for (const auto& g : guides) {
    if (!std::isfinite(g.value)) continue;
    if (g.vertical) {
      const double p = mx(g.value);
      o += "<line x1=\"" + px(p) + "\" y1=\"" + px(top) + "\" x2=\"" + px(p) + "\" y2=\"" +
           px(top + plot_h) + "\" stroke=\"" + kGuideColor + "\" stroke-dasharray=\"4 3\"/>\n";
      // Near the right edge the label goes to the left of the line, to stay in the plot.
      const bool flip = p > left + 0.8 * plot_w;
      o += "<text x=\"" + px(flip ? p - 3 : p + 3) + "\" y=\"" + px(top + 12) + "\"" +
           (flip ? " text-anchor=\"end\"" : "") + " fill=\"" + kGuideColor + "\">" + esc(g.label) +
           "</text>\n";
    } else {
      const double p = my(g.value);
      o += "<line x1=\"" + px(left) + "\" y1=\"" + px(p) + "\" x2=\"" + px(left + plot_w) +
           "\" y2=\"" + px(p) + "\" stroke=\"" + kGuideColor + "\" stroke-dasharray=\"4 3\"/>\n";
      o += "<text x=\"" + px(left + plot_w - 4) + "\" y=\"" + px(p - 4) +
           "\" text-anchor=\"end\" fill=\"" + kGuideColor + "\">" + esc(g.label) + "</text>\n";
    }
  }
  int drawn = 0;
  for (const auto& s : series) {
    std::string pts;
    int n = 0;
    for (const auto& p : s.points) {
      if (!finitePoint(p)) continue;
      if (n++) pts += " ";
      pts += px(mx(p[0])) + "," + px(my(p[1]));
    }
    if (n < 2) continue;
    ++drawn;
    o += "<polyline fill=\"none\" stroke=\"" + s.color + "\" stroke-width=\"" + px(s.width_px) +
         "\"" + (s.dashed ? " stroke-dasharray=\"6 4\"" : "") + " points=\"" + pts + "\"/>\n";
  }
  for (const auto& m : markers) {
    if (!std::isfinite(m.x) || !std::isfinite(m.y)) continue;
    const double x = mx(m.x), y = my(m.y);
    if (m.shape == Marker::Shape::kCircle)
      o += "<circle cx=\"" + px(x) + "\" cy=\"" + px(y) + "\" r=\"5\" fill=\"" + m.color +
           "\" stroke=\"black\"/>\n";
    else
      o += "<rect x=\"" + px(x - 4.5) + "\" y=\"" + px(y - 4.5) +
           "\" width=\"9\" height=\"9\" fill=\"" + m.color + "\" stroke=\"black\"/>\n";
    o += "<text x=\"" + px(x + 7) + "\" y=\"" + px(y - 7) + "\">" + esc(m.label) + "</text>\n";
  }
  o += "</g>\n";
  if (drawn == 0 && !note.empty())
    o += "<text x=\"" + px(left + plot_w / 2) + "\" y=\"" + px(top + plot_h / 2) +
         "\" text-anchor=\"middle\" fill=\"" + kGuideColor + "\">" + esc(note) + "</text>\n";

  for (std::size_t i = 0; i < legend.size(); ++i) {
    const auto& item = legend[i];
    const double x = legend_pos[i][0], y = legend_pos[i][1];
    if (item.kind == 0)
      o += "<line x1=\"" + px(x) + "\" y1=\"" + px(y) + "\" x2=\"" + px(x + 28) + "\" y2=\"" +
           px(y) + "\" stroke=\"" + item.color + "\" stroke-width=\"2\"" +
           (item.dashed ? " stroke-dasharray=\"6 4\"" : "") + "/>\n";
    else if (item.kind == 1)
      o += "<circle cx=\"" + px(x + 14) + "\" cy=\"" + px(y) + "\" r=\"5\" fill=\"" + item.color +
           "\" stroke=\"black\"/>\n";
    else
      o += "<rect x=\"" + px(x + 9.5) + "\" y=\"" + px(y - 4.5) +
           "\" width=\"9\" height=\"9\" fill=\"" + item.color + "\" stroke=\"black\"/>\n";
    o += "<text x=\"" + px(x + 34) + "\" y=\"" + px(y + 4) + "\">" + esc(item.label) + "</text>\n";
  }
  o += "</svg>\n";
  return o;
}

namespace {

// CA the figures use for a human: the rebuilt interaction CA when complete, else the last window.
const std::vector<double>* figureCa(const RunLog& run, const HumanAnalysis& h, bool* interaction) {
  *interaction = h.interaction_ca_complete && !h.interaction_ca_m.empty();
  if (*interaction) return &h.interaction_ca_m;
  if (h.last_assessment && !run.assessments[*h.last_assessment].ca_m.empty())
    return &run.assessments[*h.last_assessment].ca_m;
  return nullptr;
}

double tauOf(const RunLog& run, const RunAnalysis& analysis, double fallback) {
  for (const auto& h : analysis.humans)
    if (h.last_assessment) {
      const double tau = run.assessments[*h.last_assessment].tau_m;
      if (std::isfinite(tau)) return tau;
    }
  return fallback;
}

}  // namespace

std::string trajectoriesSvg(const RunLog& run, const RunAnalysis& analysis,
                            const std::string& name) {
  SvgPlot plot;
  plot.equal_aspect = true;
  plot.x_label = "x [m]";
  plot.y_label = "y [m]";
  plot.note = "no agent states in the log";

  SvgPlot::Series robot{"robot", kRobotColor, {}, false, 2.5};
  std::map<std::int32_t, std::vector<std::array<double, 2>>> humans;
  for (const auto& s : run.agent_states) {
    robot.points.push_back({s.robot.x_m, s.robot.y_m});
    for (const auto& h : s.humans) humans[h.id].push_back({h.x_m, h.y_m});
  }
  plot.series.push_back(std::move(robot));

  std::string round_note;
  for (std::size_t i = 0; i < analysis.humans.size(); ++i) {
    const HumanAnalysis& h = analysis.humans[i];
    const std::string color = humanColor(i);
    const std::string id = std::to_string(h.id);
    if (auto it = humans.find(h.id); it != humans.end())
      plot.series.push_back({"human " + id, color, it->second, false, 2.5});
    // The reference path the human's CA is measured against: the first one published.
    for (const auto& msg : run.reference_paths) {
      const auto path = std::find_if(msg.paths.begin(), msg.paths.end(),
                                     [&](const path_t& p) { return p.agent_id == h.id; });
      if (path == msg.paths.end() || path->num_points < 2) continue;
      SvgPlot::Series ref{"human " + id + " reference path", color, {}, true, 1.2};
      const std::size_t n = std::min(path->x_m.size(), path->y_m.size());
      for (std::size_t k = 0; k < n; ++k) ref.points.push_back({path->x_m[k], path->y_m[k]});
      plot.series.push_back(std::move(ref));
      break;
    }
    if (h.first_round_situation) {
      const auto& s = run.situations[*h.first_round_situation];
      const std::string suffix = analysis.humans.size() > 1 ? " (human " + id + ")" : "";
      plot.markers.push_back(
          {"CP_h" + suffix, color, s.cp_h_x_m, s.cp_h_y_m, SvgPlot::Marker::Shape::kCircle});
      plot.markers.push_back(
          {"CP_r" + suffix, kRobotColor, s.cp_r_x_m, s.cp_r_y_m, SvgPlot::Marker::Shape::kSquare});
      if (round_note.empty())
        round_note = ", CP at t=" + fixed(utimeToS(s.utime), 1) + " s (t_cross " +
                     fixed(s.t_cross_s, 1) + " s)";
    }
  }
  plot.title = name + ": trajectories" + round_note;
  return plot.render();
}

std::string caSvg(const RunLog& run, const RunAnalysis& analysis, const std::string& name,
                  const FigureOptions& options) {
  SvgPlot plot;
  plot.x_label = "simulated time [s]";
  plot.y_label = "CA [m] (> 0: away from the robot)";
  plot.note = "no CA recorded";
  const double tau = tauOf(run, analysis, options.tau_m);
  plot.guides.push_back({false, 0.0, ""});
  plot.guides.push_back({false, tau, "tau " + fixed(tau, 2) + " m"});
  bool all_interaction = true;
  for (std::size_t i = 0; i < analysis.humans.size(); ++i) {
    const HumanAnalysis& h = analysis.humans[i];
    bool interaction = false;
    const std::vector<double>* ca = figureCa(run, h, &interaction);
    if (!ca) continue;
    all_interaction = all_interaction && interaction;
    const double t0 = h.recorder_start_s.value_or(0.0);
    // A window shown alone starts where its samples are in the interaction.
    const std::size_t offset =
        interaction ? 0
                    : static_cast<std::size_t>(std::max<std::int64_t>(
                          0, std::int64_t{run.assessments[*h.last_assessment].interaction_samples} -
                                 static_cast<std::int64_t>(ca->size())));
    SvgPlot::Series s{"human " + std::to_string(h.id) + (interaction ? "" : " (last window)"),
                      humanColor(i),
                      {},
                      false,
                      2.0};
    for (std::size_t k = 0; k < ca->size(); ++k)
      s.points.push_back(
          {t0 + static_cast<double>(k + offset) * options.sample_period_s, (*ca)[k]});
    plot.series.push_back(std::move(s));
    if (interaction)
      for (const std::size_t start : h.window_starts)
        if (start > 0)
          plot.guides.push_back({true, t0 + static_cast<double>(start) * options.sample_period_s,
                                 "reset (human " + std::to_string(h.id) + ")"});
  }
  plot.title = name + ": CA over time (" +
               (all_interaction ? "whole interaction" : "last recording window") + ", every " +
               fixed(options.sample_period_s, 2) + " s)";
  return plot.render();
}

std::string cmGammaSvg(const RunLog& run, const RunAnalysis& analysis, const std::string& name,
                       const FigureOptions& options) {
  SvgPlot plot;
  plot.x_label = "gamma";
  plot.y_label = "CM [m]";
  plot.note = "no CA recorded";
  const double tau = tauOf(run, analysis, options.tau_m);
  plot.guides.push_back({false, tau, "tau " + fixed(tau, 2) + " m"});
  plot.guides.push_back({true, 0.98, "gamma 0.98"});
  bool all_interaction = true;
  for (std::size_t i = 0; i < analysis.humans.size(); ++i) {
    const HumanAnalysis& h = analysis.humans[i];
    bool interaction = false;
    const std::vector<double>* ca = figureCa(run, h, &interaction);
    if (!ca) continue;
    all_interaction = all_interaction && interaction;
    SvgPlot::Series s{"human " + std::to_string(h.id) + (interaction ? "" : " (last window)"),
                      humanColor(i),
                      {},
                      false,
                      2.0};
    for (int k = 0; k <= 50; ++k) {
      const double gamma = 0.5 + 0.01 * k;
      const auto cm = assessment::discountedMean(*ca, gamma);
      if (cm) s.points.push_back({gamma, *cm});
    }
    plot.series.push_back(std::move(s));
  }
  plot.title = name + ": CM as a function of gamma (" +
               (all_interaction ? "whole interaction" : "last recording window") + ")";
  return plot.render();
}

std::string safeFileStem(const std::string& name) {
  // The name comes from the log, i.e. from any bus peer: only a plain file name may reach the
  // file system, so '/', "..", a leading '.' or '-' and every other byte cannot leave out_dir.
  constexpr std::size_t kMaxStem = 100;
  std::string out;
  for (const char c : name) {
    if (out.size() >= kMaxStem) break;
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '_' || c == '-' || c == '.';
    out += plain ? c : '_';
  }
  std::size_t lead = 0;
  while (lead < out.size() && (out[lead] == '.' || out[lead] == '-')) ++lead;
  out.erase(0, lead);
  return out.empty() ? std::string("run") : out;
}

FigurePaths writeFigures(const RunLog& run, const RunAnalysis& analysis, const std::string& out_dir,
                         const std::string& name, const FigureOptions& options) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw std::runtime_error("cannot create " + out_dir + ": " + ec.message());
  FigurePaths paths;
  const std::string base = (std::filesystem::path(out_dir) / safeFileStem(name)).string();
  paths.trajectories = base + "_trajectories.svg";
  paths.ca = base + "_ca.svg";
  paths.cm_gamma = base + "_cm_gamma.svg";
  writeTextFile(paths.trajectories, trajectoriesSvg(run, analysis, name));
  writeTextFile(paths.ca, caSvg(run, analysis, name, options));
  writeTextFile(paths.cm_gamma, cmGammaSvg(run, analysis, name, options));
  return paths;
}

namespace {

struct SummaryCurve {
  std::string label;
  std::vector<double> ca_m;
  double tau_m{std::nan("")};
};

std::vector<SummaryCurve> summaryCurves(const Json& summary) {
  std::vector<SummaryCurve> curves;
  const Json* list = member(summary, "scenarios");
  if (!list) throw std::runtime_error("not a coopnav summary (no \"scenarios\" array)");
  for (const auto& s : elements(list)) {
    const Json* name = member(s, "scenario");
    const auto& humans = elements(member(s, "humans"));
    for (const auto& h : humans) {
      const auto& ca = elements(member(h, "ca_m"));
      if (ca.empty()) continue;
      SummaryCurve c;
      c.label = name ? stringValue(name) : "?";
      if (humans.size() > 1) {
        const Json* id = member(h, "id");
        c.label += " human " + jsonNumber(id ? numberValue(id) : -1.0);
      }
      for (const auto& v : ca) c.ca_m.push_back(numberValue(&v));
      if (const Json* tau = member(h, "tau_m")) c.tau_m = numberValue(tau);
      curves.push_back(std::move(c));
    }
  }
  return curves;
}

double firstTau(const std::vector<SummaryCurve>& curves, double fallback) {
  for (const auto& c : curves)
    if (std::isfinite(c.tau_m)) return c.tau_m;
  return fallback;
}

}  // namespace

std::string summaryCaSvg(const Json& summary, const FigureOptions& options) {
  const auto curves = summaryCurves(summary);
  SvgPlot plot;
  plot.title = "CA over time, every scenario (every " + fixed(options.sample_period_s, 2) + " s)";
  plot.x_label = "time since the recorder start [s]";
  plot.y_label = "CA [m] (> 0: away from the robot)";
  plot.note = "no CA recorded";
  const double tau = firstTau(curves, options.tau_m);
  plot.guides.push_back({false, 0.0, ""});
  plot.guides.push_back({false, tau, "tau " + fixed(tau, 2) + " m"});
  for (std::size_t i = 0; i < curves.size(); ++i) {
    SvgPlot::Series s{curves[i].label, humanColor(i), {}, false, 2.0};
    for (std::size_t k = 0; k < curves[i].ca_m.size(); ++k)
      s.points.push_back({static_cast<double>(k) * options.sample_period_s, curves[i].ca_m[k]});
    plot.series.push_back(std::move(s));
  }
  return plot.render();
}

std::string summaryCmGammaSvg(const Json& summary, const FigureOptions& options) {
  const auto curves = summaryCurves(summary);
  SvgPlot plot;
  plot.title = "CM as a function of gamma, every scenario";
  plot.x_label = "gamma";
  plot.y_label = "CM [m]";
  plot.note = "no CA recorded";
  const double tau = firstTau(curves, options.tau_m);
  plot.guides.push_back({false, tau, "tau " + fixed(tau, 2) + " m"});
  plot.guides.push_back({true, 0.98, "gamma 0.98"});
  for (std::size_t i = 0; i < curves.size(); ++i) {
    SvgPlot::Series s{curves[i].label, humanColor(i), {}, false, 2.0};
    for (int k = 0; k <= 50; ++k) {
      const double gamma = 0.5 + 0.01 * k;
      if (const auto cm = assessment::discountedMean(curves[i].ca_m, gamma))
        s.points.push_back({gamma, *cm});
    }
    plot.series.push_back(std::move(s));
  }
  return plot.render();
}

FigurePaths writeSummaryFigures(const Json& summary, const std::string& out_dir,
                                const FigureOptions& options) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw std::runtime_error("cannot create " + out_dir + ": " + ec.message());
  FigurePaths paths;
  paths.ca = (std::filesystem::path(out_dir) / "summary_ca.svg").string();
  paths.cm_gamma = (std::filesystem::path(out_dir) / "summary_cm_gamma.svg").string();
  writeTextFile(paths.ca, summaryCaSvg(summary, options));
  writeTextFile(paths.cm_gamma, summaryCmGammaSvg(summary, options));
  return paths;
}

}  // namespace coopnav::ctl
