#pragma once
/// @file The figures of a recorded run as SVG text (no plotting dependency), mirroring the
/// paper's Figs. 5-8: trajectories with CP_h / CP_r at the first round, CA over time per human,
/// and CM as a function of γ per human. Deterministic output for identical logs.

#include <array>
#include <string>
#include <vector>

#include "json.hpp"
#include "logfile/log_reader.hpp"
#include "run_analysis.hpp"

namespace coopnav::ctl {

/// A generic x/y line plot with metre/second axes, legend, point markers and guide lines.
struct SvgPlot {
  struct Series {
    std::string label;
    std::string color;
    std::vector<std::array<double, 2>> points;  ///< non-finite points are left out
    bool dashed{false};
    double width_px{2.0};
  };
  struct Marker {
    enum class Shape { kCircle, kSquare };
    std::string label;
    std::string color;
    double x{0.0};
    double y{0.0};
    Shape shape{Shape::kCircle};
  };
  struct Guide {
    bool vertical{false};
    double value{0.0};
    std::string label;
  };
  std::string title;
  std::string x_label;
  std::string y_label;
  bool equal_aspect{false};  ///< same scale on both axes (maps)
  std::vector<Series> series;
  std::vector<Marker> markers;
  std::vector<Guide> guides;
  std::string note;  ///< shown in the plot when there is nothing to draw

  /// One <polyline> per series with at least two finite points; axes, ticks and legend use other
  /// elements, so tests can count series by "<polyline".
  std::string render() const;
};

struct FigureOptions {
  double sample_period_s{0.1};  ///< [s] path assessor's CA sampling period (its config default)
  double tau_m{0.4};            ///< [m] drawn when the log carries no τ
};

struct FigurePaths {
  std::string trajectories;
  std::string ca;
  std::string cm_gamma;
};

std::string trajectoriesSvg(const RunLog& run, const RunAnalysis& analysis,
                            const std::string& name);
std::string caSvg(const RunLog& run, const RunAnalysis& analysis, const std::string& name,
                  const FigureOptions& options = {});
std::string cmGammaSvg(const RunLog& run, const RunAnalysis& analysis, const std::string& name,
                       const FigureOptions& options = {});

/// A file name stem made of name that stays inside its directory: every byte but [A-Za-z0-9._-]
/// becomes '_', leading '.' and '-' are dropped (no "..", no hidden file, no option-like name),
/// at most 100 bytes; "run" when nothing is left.
std::string safeFileStem(const std::string& name);

/// Writes <out_dir>/<safeFileStem(name)>_{trajectories,ca,cm_gamma}.svg (creating out_dir). Throws
/// std::runtime_error when a file cannot be written.
FigurePaths writeFigures(const RunLog& run, const RunAnalysis& analysis, const std::string& out_dir,
                         const std::string& name, const FigureOptions& options = {});

/// Figures across the scenarios of a summary.json (its "ca_m" per human): <out_dir>/
/// summary_ca.svg (CA against time since the recorder start) and summary_cm_gamma.svg (CM against
/// γ, as the paper's single γ-vs-CM figure). Returns {"", ca, cm_gamma}.
FigurePaths writeSummaryFigures(const Json& summary, const std::string& out_dir,
                                const FigureOptions& options = {});
std::string summaryCaSvg(const Json& summary, const FigureOptions& options = {});
std::string summaryCmGammaSvg(const Json& summary, const FigureOptions& options = {});

}  // namespace coopnav::ctl
