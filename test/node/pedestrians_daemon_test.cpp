// `coopnav_ctl pedestrians --daemon` (tools/ctl/pedestrians_daemon.hpp): the 344 real walker-runs
// of test/data/pedestrians through the real coopnav_path_assessor process over this test's udpm
// port give the in-process replay's CMs (and so its scores), under both profiles and a window that
// STARTs in the past (the avoidance onset).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "test_paths.hpp"
#include "test_util.hpp"

namespace coopnav {
namespace {

struct CtlRun {
  int exit_code{-1};
  std::string out;
};

CtlRun runCtl(const std::string& args) {
  const std::string ctl = ::coopnav::test::binaryDir() + "/tools/coopnav_ctl";
  CtlRun r;
  if (!std::filesystem::exists(ctl)) {
    ADD_FAILURE() << ctl << " is missing: build coopnav_ctl";
    return r;
  }
  FILE* p = ::popen((ctl + " " + args).c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int st = ::pclose(p);
  r.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

// The value after "RESULT <name> " in out, or NaN.
double result(const std::string& out, const std::string& name) {
  const std::string key = "RESULT " + name + " ";
  const auto at = out.find(key);
  if (at == std::string::npos) return std::nan("");
  return std::stod(out.substr(at + key.size()));
}

std::string daemonArgs(const std::string& profile_file, const std::string& window) {
  return "pedestrians " + ::coopnav::test::testDataDir() +
         "/pedestrians/headon_pairs.json --daemon --window " + window + " --config " +
         ::coopnav::test::sourceDir() + "/config/" + profile_file + " --path-assessor " +
         test::daemonPath("path_assessor") + " --lcm-url '" + test::testLcmUrl() + "'";
}

TEST(PedestriansDaemon, PaperProfileMatchesInProcessReplay) {
  const CtlRun r = runCtl(daemonArgs("path_assessor.yaml", "round1"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_LE(result(r.out, "pedestrians_daemon_max_abs_dcm_m"), 1e-9) << r.out;
  EXPECT_EQ(result(r.out, "pedestrians_daemon_sample_mismatches"), 0.0) << r.out;
  // The daemon's scores are the in-process ones (tools/ctl/README.md, "Real pedestrians").
  EXPECT_NEAR(result(r.out, "pedestrians_pair_ranking"), 107.0 / 164.0, 1e-4) << r.out;
  // And the same settings given as the in-process command's options.
  const CtlRun in_process =
      runCtl("pedestrians " + ::coopnav::test::testDataDir() + "/pedestrians/headon_pairs.json");
  ASSERT_EQ(in_process.exit_code, 0) << in_process.out;
  EXPECT_EQ(result(r.out, "pedestrians_is_contributing_agreement"),
            result(in_process.out, "pedestrians_is_contributing_agreement"));
}

TEST(PedestriansDaemon, CalibratedProfileWithOnsetWindowMatchesInProcessReplay) {
  const CtlRun r = runCtl(daemonArgs("path_assessor_calibrated.yaml", "onset"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_LE(result(r.out, "pedestrians_daemon_max_abs_dcm_m"), 1e-9) << r.out;
  EXPECT_EQ(result(r.out, "pedestrians_daemon_sample_mismatches"), 0.0) << r.out;
  EXPECT_GE(result(r.out, "pedestrians_pair_ranking"), 0.85) << r.out;
  EXPECT_GE(result(r.out, "pedestrians_is_contributing_agreement"), 0.85) << r.out;
}

TEST(PedestriansDaemon, MissingDaemonIsAClearError) {
  const CtlRun r = runCtl("pedestrians " + ::coopnav::test::testDataDir() +
                          "/pedestrians/headon_pairs.json --daemon --path-assessor /nonexistent "
                          "--lcm-url '" +
                          test::testLcmUrl() + "' 2>&1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("/nonexistent: not an executable"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace coopnav
