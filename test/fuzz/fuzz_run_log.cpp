// coopnav_ctl's reading of a recorded run (an lcm-logger file): event framing, the decoding of
// every type the log tools keep (agent states, situations, path assessments, utterances, robot
// actions, recorder commands, sim_status_t, reference paths, daemon_status_t), then the analysis,
// transcript and summary built from them. A log is untrusted input
// (daemons/common/logfile/log_reader.hpp): nothing in it may crash the tools or make them throw
// anything but std::runtime_error.
#include <stdexcept>

#include "fuzz_util.hpp"
#include "logfile/log_reader.hpp"
#include "run_analysis.hpp"
#include "summary.hpp"
#include "transcript.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coopnav;
  const std::string path = fuzz::scratch().write("run.lcm", data, size);
  ctl::RunLog run;
  try {
    run = ctl::readRunLog(path);
  } catch (const std::runtime_error&) {
    return 0;
  }
  const ctl::RunAnalysis analysis = ctl::analyseRun(run);
  ctl::TranscriptOptions options;
  options.include_daemon_status = true;
  const auto entries = ctl::buildTranscript(run, analysis, options);
  (void)ctl::formatTranscript(analysis.scenario, entries);
  (void)ctl::summarizeRun(run, analysis, "run.lcm");
  return 0;
}
