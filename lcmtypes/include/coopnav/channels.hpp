#pragma once
/// @file Every LCM channel name of coopnav, in one place. UPPER_SNAKE, <= 63 bytes (LCM limit).
/// Scripts read the same names from lcmtypes/channels.txt, checked against this file by a test.

namespace coopnav::channels {

inline constexpr const char* kAgentStates = "COOPNAV_AGENT_STATES";        // agent_states_t
inline constexpr const char* kGoals = "COOPNAV_GOALS";                     // goals_t
inline constexpr const char* kGoalEstimates = "COOPNAV_GOAL_ESTIMATES";    // goal_estimates_t
inline constexpr const char* kBands = "COOPNAV_BANDS";                     // bands_t
inline constexpr const char* kReferencePaths = "COOPNAV_REFERENCE_PATHS";  // reference_paths_t
inline constexpr const char* kRobotCmd = "COOPNAV_ROBOT_CMD";              // velocity_command_t
inline constexpr const char* kDistanceRequest = "COOPNAV_DIST_REQ";        // distance_request_t
/// Replies go to kDistanceReplyPrefix + <client name> (distance_reply_t).
inline constexpr const char* kDistanceReplyPrefix = "COOPNAV_DIST_REP_";
inline constexpr const char* kSituation = "COOPNAV_SITUATION";             // situation_t
inline constexpr const char* kPathAssessment = "COOPNAV_PATH_ASSESSMENT";  // path_assessment_t
inline constexpr const char* kPathAssessorControl =
    "COOPNAV_PATH_ASSESSOR_CONTROL";                                 // path_assessor_control_t
inline constexpr const char* kUtterance = "COOPNAV_UTTERANCE";       // utterance_t
inline constexpr const char* kRobotAction = "COOPNAV_ROBOT_ACTION";  // robot_action_t
inline constexpr const char* kStatus = "COOPNAV_STATUS";             // daemon_status_t
inline constexpr const char* kStepAck = "COOPNAV_STEP_ACK";          // step_ack_t
inline constexpr const char* kSimStatus = "COOPNAV_SIM_STATUS";      // sim_status_t
/// A laser scan with its sensor pose in the map frame (world_sim or coopnav_ros2_bridge).
inline constexpr const char* kScan = "COOPNAV_SCAN";  // laser_scan_t

}  // namespace coopnav::channels
