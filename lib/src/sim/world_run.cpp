#include "coopnav/sim/world_run.hpp"

#include <cstdio>
#include <sstream>
#include <utility>

namespace coopnav::sim {

namespace {

/// A number as the sentences have always printed it (iostream's default: "20", "0.5").
std::string fmt(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

/// Two decimals, as a time or speed in a sentence.
std::string fixed2(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", x);
  return buf;
}

}  // namespace

RunEnd runEndOf(SimStatus status) {
  switch (status) {
    case SimStatus::kGoalsReached:
      return RunEnd::kGoalsReached;
    case SimStatus::kCollision:
      return RunEnd::kCollision;
    case SimStatus::kTimeLimit:
      return RunEnd::kTimeLimit;
    case SimStatus::kStandstill:
      return RunEnd::kStandstill;
    case SimStatus::kRunning:
      break;
  }
  return RunEnd::kError;  // not an end: a caller's mistake, never a run's outcome
}

std::string contactDetail(const RobotHumanContact& c, double fault_speed_m_s) {
  const std::string human = "human " + std::to_string(c.human_id);
  const std::string at = " at t " + fixed2(c.t_s) + " s";
  if (c.robot_at_fault)
    return "the robot drove into " + human + " at " + fixed2(c.robot_speed_towards_m_s) + " m/s" +
           at;
  if (c.robot_speed_towards_m_s < -fault_speed_m_s)
    return human + " walked into the robot moving away from it at " +
           fixed2(-c.robot_speed_towards_m_s) + " m/s" + at;
  return human + " walked into the robot at rest" + at;
}

std::string endDetail(const StepResult& r, const SimSummary& sum, const EndContext& ctx) {
  switch (r.status) {
    case SimStatus::kCollision:
      for (const SimEvent& e : r.events) {
        if (e.kind != SimEvent::Kind::kCollision || e.agent_id != kRobotId) continue;
        if (e.other_id == kWallId) return "robot collided with a wall at t = " + fmt(e.t_s) + " s";
        if (sum.first_contact && sum.first_contact->human_id == e.other_id)
          return contactDetail(*sum.first_contact, ctx.contact_fault_speed_m_s);
        return "robot collided with human " + std::to_string(e.other_id) + " at t = " + fmt(e.t_s) +
               " s";
      }
      return "robot collision";
    case SimStatus::kStandstill: {
      std::string robot =
          ctx.robot_mode ? "was " + *ctx.robot_mode : std::string("was never commanded");
      if (sum.robot_goal_time_s >= 0.0 && (!ctx.robot_mode || !ctx.robot_mode_at_goal))
        robot += " (at its goal)";
      return "standstill: no agent moved more than " + fmt(ctx.standstill_distance_m) + " m for " +
             fmt(ctx.standstill_time_s) + " s; the robot " + robot +
             (ctx.last_said.empty() ? ", had said nothing" : ", last said " + ctx.last_said);
    }
    case SimStatus::kGoalsReached:
      return "robot reached its goal at t = " + fmt(sum.robot_goal_time_s) +
             " s and every human its own";
    case SimStatus::kTimeLimit:
      return "time limit of " + fmt(ctx.time_limit_s) + " s reached" +
             (sum.robot_goal_time_s >= 0.0 ? "" : " before the robot reached its goal");
    case SimStatus::kRunning:
      break;
  }
  return "";
}

WorldRun::WorldRun(std::vector<std::string> participants, double step_timeout_s)
    : participants_(std::move(participants)), step_timeout_s_(step_timeout_s) {}

bool WorldRun::heard(const std::string& name) {
  return phase_ == Phase::kWaitingReady && ready_.insert(name).second;
}

std::string WorldRun::missing() const {
  std::string out;
  for (const auto& p : participants_)
    if (!ready_.count(p)) out += (out.empty() ? "" : ", ") + p;
  return out;
}

WorldRun::Finish WorldRun::neverReady(double wait_ready_timeout_s) const {
  return {RunEnd::kParticipantTimeout,
          "participant(s) never sent a status within wait_ready_timeout_s = " +
              fmt(wait_ready_timeout_s) + " s: " + missing(),
          false};
}

std::optional<WorldRun::Finish> WorldRun::simulationEnded(RunEnd end, std::string detail,
                                                          bool hold) {
  Finish f{end, std::move(detail), false};
  if (!hold) return f;
  ending_ = std::move(f);
  return std::nullopt;
}

std::optional<WorldRun::Finish> WorldRun::stepAcknowledged(std::int64_t step, bool degraded,
                                                           const std::string& missing) {
  if (ending_) {
    // How the run ended does not depend on the acks of its last step; a participant silent on
    // it is named, never ignored.
    Finish f = *ending_;
    if (degraded) {
      f.detail += " (its last step " + std::to_string(step) +
                  " was not acknowledged within step_timeout_s = " + fmt(step_timeout_s_) +
                  " s by: " + missing + ")";
      f.last_step_unacknowledged = true;
    }
    return f;
  }
  if (degraded)
    return Finish{RunEnd::kParticipantTimeout,
                  "no acknowledgement of step " + std::to_string(step) +
                      " within step_timeout_s = " + fmt(step_timeout_s_) + " s from: " + missing,
                  false};
  return std::nullopt;
}

}  // namespace coopnav::sim
