// The shell scripts read channel names from lcmtypes/channels.txt: keep it equal to channels.hpp.
#include "coopnav/channels.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "test_paths.hpp"

namespace coopnav {
namespace {

TEST(ChannelsTest, TextListMatchesTheHeaderAndFitsLcmLimit) {
  std::ifstream in(::coopnav::test::sourceDir() + "/lcmtypes/channels.txt");
  ASSERT_TRUE(in);
  std::set<std::string> listed;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string name;
    s >> name;
    listed.insert(name);
  }
  const std::set<std::string> header{channels::kAgentStates,
                                     channels::kGoals,
                                     channels::kGoalEstimates,
                                     channels::kBands,
                                     channels::kReferencePaths,
                                     channels::kRobotCmd,
                                     channels::kDistanceRequest,
                                     channels::kDistanceReplyPrefix,
                                     channels::kSituation,
                                     channels::kPathAssessment,
                                     channels::kPathAssessorControl,
                                     channels::kUtterance,
                                     channels::kRobotAction,
                                     channels::kStatus,
                                     channels::kStepAck,
                                     channels::kSimStatus,
                                     channels::kScan};
  EXPECT_EQ(listed, header);
  for (const auto& c : header) EXPECT_LE(c.size(), 40u) << c;  // room for reply suffixes (63 max)
}

}  // namespace
}  // namespace coopnav
