#pragma once
// The decode path of each subscribed lcmtype, as the daemons run it: decodeOrReject (Runtime's
// decoding), then the conversion into lib/ types and its validation. An accepted message is
// converted back (what a daemon republishes or a test compares) and must be accepted again.
// RejectedMessage is the expected refusal; every other exception escapes and is a finding.

#include <cmath>
#include <cstdint>
#include <string>

#include "coopnav/daemon_status_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "fuzz_util.hpp"
#include "wire/assessment.hpp"
#include "wire/conversions.hpp"
#include "wire/dialogue.hpp"

namespace coopnav::fuzz {

/// LCM 1.3.1's encoder writes a string up to its first NUL but sizes it by size(), so a string
/// holding a NUL cannot be re-encoded faithfully. A received one decodes (the decoder keeps the
/// bytes) and no daemon republishes a received string, so the round trip skips such messages.
inline bool encodable(const std::string& s) { return s.find('\0') == std::string::npos; }
template <class Msg>
bool stringsEncodable(const Msg&) {
  return true;
}
inline bool stringsEncodable(const situation_t& m) { return encodable(m.reason); }
inline bool stringsEncodable(const path_assessor_control_t& m) { return encodable(m.reason); }
inline bool stringsEncodable(const utterance_t& m) { return encodable(m.text); }
inline bool stringsEncodable(const robot_action_t& m) { return encodable(m.reason); }

/// Converts an accepted message's lib value back and checks the daemon accepts the result.
template <class Msg, class Value>
void requireAcceptedAgain(const Value& value) {
  const Msg back = reencode(toLcm(value));
  try {
    (void)fromLcm(back);
  } catch (const RejectedMessage&) {
    fail("a message built from an accepted one is rejected");
  }
}

/// Decodes, converts with fromLcm and, when accepted, round-trips. Returns false on a rejection.
template <class Msg>
bool convertAndRoundTrip(const ChannelInput& in) {
  Msg msg;
  if (!decodeLikeDaemon(in, &msg)) return false;
  try {
    const auto value = fromLcm(msg);
    if (stringsEncodable(msg)) requireAcceptedAgain<Msg>(value);
    return true;
  } catch (const RejectedMessage&) {
    return false;
  }
}

// agent_states_t (band_source, path_assessor, dialogue_manager).
inline void agentStates(const ChannelInput& in) {
  agent_states_t msg;
  if (!decodeLikeDaemon(in, &msg)) return;
  try {
    const AgentStatesSnapshot s = fromLcm(msg);
    if (s.humans.size() != static_cast<std::size_t>(msg.num_humans))
      fail("agent states: humans lost in conversion");
    for (const auto& h : s.humans)
      if (s.human(h.id) != &h) fail("agent states: human lookup does not find its own id");
    requireAcceptedAgain<agent_states_t>(s);
  } catch (const RejectedMessage&) {
  }
}

// goals_t (band_source).
inline void goals(const ChannelInput& in) { convertAndRoundTrip<goals_t>(in); }

// bands_t (situation_assessor, world_sim).
inline void bands(const ChannelInput& in) {
  bands_t msg;
  if (!decodeLikeDaemon(in, &msg)) return;
  try {
    const BandsSnapshot s = fromLcm(msg);
    for (const auto& [id, band] : s.humans)
      if (s.humanBand(id) != &band) fail("bands: band lookup does not find its own id");
    requireAcceptedAgain<bands_t>(s);
  } catch (const RejectedMessage&) {
  }
}

// reference_paths_t (situation_assessor, path_assessor).
inline void referencePaths(const ChannelInput& in) { convertAndRoundTrip<reference_paths_t>(in); }

// velocity_command_t (world_sim).
inline void velocityCommand(const ChannelInput& in) { convertAndRoundTrip<velocity_command_t>(in); }

// path_assessor_control_t (path_assessor).
inline void pathAssessorControl(const ChannelInput& in) {
  convertAndRoundTrip<path_assessor_control_t>(in);
}

// situation_t (dialogue_manager): the record, and the snapshot the decision logic reads.
inline void situation(const ChannelInput& in) {
  situation_t msg;
  if (!decodeLikeDaemon(in, &msg)) return;
  try {
    const SituationRecord r = fromLcm(msg);
    const dialogue::SituationSnapshot s = situationSnapshotFromLcm(msg);
    if (s.t_cross_s && !(std::isfinite(*s.t_cross_s) && *s.t_cross_s >= 0.0))
      fail("situation: accepted t_CROSS is not a finite time >= 0");
    if (stringsEncodable(msg)) requireAcceptedAgain<situation_t>(r);
  } catch (const RejectedMessage&) {
  }
}

// path_assessment_t (dialogue_manager; the trace's gamma sweep reads it too).
inline void pathAssessment(const ChannelInput& in) {
  path_assessment_t msg;
  if (!decodeLikeDaemon(in, &msg)) return;
  try {
    const PathAssessmentRecord r = fromLcm(msg);
    const dialogue::PathSnapshot s = pathSnapshotFromLcm(msg);
    if (s.cm_window_m && !std::isfinite(*s.cm_window_m)) fail("path assessment: CM not finite");
    for (const double gamma : {msg.gamma, 0.5, 1.0}) {
      const std::optional<double> cm = cmForGamma(msg, gamma);
      if (cm && !std::isfinite(*cm)) fail("path assessment: CM for a gamma is not finite");
    }
    requireAcceptedAgain<path_assessment_t>(r);
  } catch (const RejectedMessage&) {
  }
}

// utterance_t (world_sim's responsive humans).
inline void utterance(const ChannelInput& in) {
  utterance_t msg;
  if (!decodeLikeDaemon(in, &msg)) return;
  try {
    const UtteranceMsg u = fromLcm(msg);
    if (!stringsEncodable(msg)) return;
    const utterance_t back = reencode(toLcm(u.stamp, u.utterance, u.t_cross_s, u.slot, u.group));
    (void)fromLcm(back);
  } catch (const RejectedMessage&) {
  }
}

// robot_action_t (band_source).
inline void robotAction(const ChannelInput& in) {
  robot_action_t msg;
  if (!decodeLikeDaemon(in, &msg)) return;
  try {
    const RobotActionMsg a = fromLcm(msg);
    if (!stringsEncodable(msg)) return;
    const robot_action_t back = reencode(toLcm(a.stamp, a.action, a.reason));
    (void)fromLcm(back);
  } catch (const RejectedMessage&) {
  }
}

// step_ack_t (every lockstep gate): the gate compares participant names and steps as they are,
// so decoding is the whole path.
inline void stepAck(const ChannelInput& in) {
  step_ack_t msg;
  (void)decodeLikeDaemon(in, &msg);
}

// daemon_status_t (world_sim waits for the daemons' first status): the name is all it reads.
inline void daemonStatus(const ChannelInput& in) {
  daemon_status_t msg;
  (void)decodeLikeDaemon(in, &msg);
}

}  // namespace coopnav::fuzz
