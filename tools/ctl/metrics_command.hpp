#pragma once
/// @file `coopnav_ctl metrics LOG... [--json F] [--csv F] [--map FILE]`: the field's metrics of
/// recorded runs (run_metrics_export.hpp, docs/metrics.md).
#include <CLI/CLI.hpp>

namespace coopnav::ctl {
void addMetricsCommand(CLI::App& app);
/// True when the metrics subcommand was given on the command line.
bool metricsCommandChosen();
/// Exit status: 0, or 1 when a log cannot be read or holds no agent states.
int runMetricsCommand();
}  // namespace coopnav::ctl
