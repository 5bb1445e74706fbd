// The worked example of docs/architecture.md (test/node/example/speed_limiter_node.hpp): it runs
// as a daemon on the step harness, and the document quotes it as it is.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "coopnav/step_ack_t.hpp"
#include "example/speed_limiter_node.hpp"
#include "test_paths.hpp"

namespace coopnav {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

agent_states_t states(std::int64_t step, double human_x_m) {
  AgentStatesSnapshot s;
  s.utime = 1'000'000 + step * 100'000;
  s.step = step;
  s.robot.id = 0;
  s.robot.kind = AgentKind::kRobot;
  AgentState h;
  h.id = 1;
  h.kind = AgentKind::kHuman;
  h.pose.x_m = human_x_m;
  s.humans.push_back(h);
  return toLcm(s);
}

velocity_command_t command(std::int64_t step) {
  VelocityCommand c;
  c.utime = 1'000'000 + step * 100'000;
  c.step = step;
  c.body = {0.6, 0.0, 0.2};
  c.mode = velocity_command_t::MODE_NAVIGATING;
  return toLcm(c);
}

TEST(ExampleDaemon, LimitsTheCommandOfEachStepNearAHumanAndAcknowledgesIt) {
  Runtime rt("speed_limiter", "memq://");
  example::SpeedLimiterNode node(example::SpeedLimiterConfig{}, rt);
  std::vector<velocity_command_t> out;
  std::vector<std::int64_t> acks;
  rt.subscribe<velocity_command_t>(
      example::SpeedLimiterNode::kOutput,
      [&](const velocity_command_t& m, std::int64_t) { out.push_back(m); });
  rt.subscribe<step_ack_t>(channels::kStepAck, [&](const step_ack_t& a, std::int64_t) {
    if (a.participant == "speed_limiter") acks.push_back(a.step);
  });
  rt.publish(channels::kRobotCmd, command(0));
  rt.publish(channels::kAgentStates, states(0, 5.0));  // far: unchanged
  rt.publish(channels::kRobotCmd, command(1));
  rt.publish(channels::kAgentStates, states(1, 1.0));  // near: halved
  for (int i = 0; i < 10; ++i) rt.spinFor(0);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].vx_m_s, 0.6);
  EXPECT_DOUBLE_EQ(out[1].vx_m_s, 0.3);
  EXPECT_DOUBLE_EQ(out[1].omega_rad_s, 0.1);
  EXPECT_EQ(acks, (std::vector<std::int64_t>{0, 1}));
}

TEST(ExampleDaemon, TheArchitectureDocumentQuotesItAsItIs) {
  const std::string header =
      readFile(::coopnav::test::sourceDir() + "/test/node/example/speed_limiter_node.hpp");
  const std::string doc = readFile(::coopnav::test::sourceDir() + "/docs/architecture.md");
  ASSERT_FALSE(header.empty());
  EXPECT_NE(doc.find(header), std::string::npos)
      << "docs/architecture.md must quote test/node/example/speed_limiter_node.hpp verbatim";
}

}  // namespace
}  // namespace coopnav
