#include "coopnav/dialogue/session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <utility>

#include "coopnav/geometry/geometry.hpp"
#include "coopnav/geometry/track_continuity.hpp"

namespace coopnav::dialogue {
namespace {

/// Ids listed in one note about a batch of them; the rest are counted.
constexpr std::size_t kIdsPerNote = 8;

// Message time: utime [us] -> seconds, and differences in double (a hostile stamp may be
// INT64_MIN or INT64_MAX; exact while both are below 2^53 us).
double seconds(std::int64_t utime) { return static_cast<double>(utime) * 1e-6; }
double diffSeconds(std::int64_t later_utime, std::int64_t earlier_utime) {
  return (static_cast<double>(later_utime) - static_cast<double>(earlier_utime)) * 1e-6;
}

/// `v` with `decimals` digits after the point (as printf's %.Nf).
std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string formatTCross(std::optional<double> t_cross_s) {
  return t_cross_s ? fixed(*t_cross_s, 2) + " s" : std::string("-");
}

std::string formatOptional(std::optional<double> v) {
  return v ? fixed(*v, 3) : std::string("unknown");
}

const char* tristateName(Tristate t) {
  return t == Tristate::kTrue ? "TRUE" : (t == Tristate::kFalse ? "FALSE" : "UNKNOWN");
}

std::string idList(const std::vector<std::int32_t>& ids) {
  std::string s;
  for (std::size_t i = 0; i < ids.size() && i < kIdsPerNote; ++i)
    s += (s.empty() ? "" : ",") + std::to_string(ids[i]);
  if (ids.size() > kIdsPerNote) s += " and " + std::to_string(ids.size() - kIdsPerNote) + " more";
  return s;
}

void note(SessionOutput& out, SessionNote::Level level, std::string text) {
  out.notes.push_back({level, std::move(text)});
}

}  // namespace

Session::Session(const SessionConfig& config, double forget_after_s, std::size_t max_ids)
    : config_(config), forget_after_s_(forget_after_s), max_ids_(max_ids), crowd_(config.crowd) {}

const HumanDecision* Session::decision(std::int32_t id) const {
  const auto it = people_.find(id);
  return it == people_.end() || !it->second.decision ? nullptr : &*it->second.decision;
}

std::size_t Session::humansKept() const {
  return static_cast<std::size_t>(std::count_if(
      people_.begin(), people_.end(), [](const auto& p) { return p.second.decision.has_value(); }));
}

std::size_t Session::longestKeptTextBytes() const {
  std::size_t n = 0;
  for (const auto& [id, p] : people_)
    if (p.decision) n = std::max(n, p.last_situation.reason.size());
  return n;
}

double Session::speechDuration(const std::string& text) const {
  const auto it = measured_s_.find(text);
  if (it != measured_s_.end()) return it->second;
  return estimateSpeechDuration(text, config_.speech_rate_wpm);
}

void Session::restamp(std::int64_t utime) {
  heard_.restamp(utime);
  present_.restamp(utime);
  for (auto& [id, p] : people_)
    if (p.seen) p.last_seen_utime = utime;
  if (latest_agents_utime_) latest_agents_utime_ = utime;
}

SessionNote Session::joinLate(const SessionInput& in) {
  std::set<std::int32_t> ids;
  for (const auto& [id, s] : in.situations) ids.insert(id);
  if (in.agents)
    for (const auto& h : in.agents->humans) ids.insert(h.id);
  for (const std::int32_t id : ids) people_[id].history_unknown = true;
  std::string list;
  for (const auto& [id, p] : people_)
    if (p.history_unknown) list += (list.empty() ? "" : ",") + std::to_string(id);
  return {SessionNote::Level::kWarn, "joined the run at step " + std::to_string(in.step) +
                                         " without its state: no decisions for humans " +
                                         (list.empty() ? "-" : list) +
                                         " (rounds already fired unknown)"};
}

// ---- one step ----

SessionOutput Session::step(const SessionInput& in) {
  SessionOutput out;
  const std::int64_t now = in.clock_utime.value_or(in.utime);
  // 1. Where the agents are: crossed detection and presence, for every human in the scene.
  std::set<std::int32_t> crossed_now;
  if (in.agents) see(*in.agents, now, crossed_now, out);
  // 2. The latest path assessment of each human, read before the decisions of this step.
  for (const auto& [id, p] : in.paths) {
    people_[id].path = p;
    heard_.touch(id, now);
  }

  // 3. Decisions, humans in id order (deterministic output order), emitted together.
  std::set<std::int32_t> ids;
  for (const auto& [id, s] : in.situations) ids.insert(id);
  for (const std::int32_t id : crossed_now)
    if (decision(id)) ids.insert(id);
  std::vector<Decided> decided;
  for (const std::int32_t id : ids) {
    const auto sit = in.situations.find(id);
    if (sit != in.situations.end()) {
      decided.push_back(
          decide(in.step, id, sit->second.stamp, sit->second.snapshot, in.clock_utime, out));
    } else {
      // Crossed on this step's agent states, no situation for it: round 3 on the last one.
      const Stamp stamp{in.agents->utime, in.step, id};
      const SituationSnapshot last = people_.at(id).last_situation;
      decided.push_back(decide(in.step, id, stamp, last, in.clock_utime, out));
    }
  }
  emitDecided(decided, out);

  // 4. Humans that left the scene end their interaction (stop the recorder, resume a dock).
  if (in.agents) endAbsent(in.step, *in.agents, out);
  // 5. Forget humans long gone (as the assessors do): a robot running for hours meets
  // thousands of tracker ids, and a tracker that reuses an id after a minute means someone
  // new, whose rounds start afresh. Ids never seen in the agent states age the same way.
  forgetStale(in, out);
  return out;
}

void Session::see(const SceneSnapshot& a, std::int64_t now, std::set<std::int32_t>& crossed_now,
                  SessionOutput& out) {
  robot_pose_ = a.robot.pose;
  robot_speed_m_s_ = std::hypot(a.robot.velocity.vx_m_s, a.robot.velocity.vy_m_s);
  robot_velocity_m_s_ = {a.robot.velocity.vx_m_s, a.robot.velocity.vy_m_s};
  robot_radius_m_ = a.robot.radius_m;
  robot_known_ = true;
  latest_agents_utime_ = latest_agents_utime_ ? std::max(*latest_agents_utime_, a.utime) : a.utime;
  continueSwitchedIds(a, out);
  for (const auto& h : a.humans) {
    Person& p = people_[h.id];
    p.seen = true;
    p.position_m = h.pose.position();
    p.velocity_m_s = {h.velocity.vx_m_s, h.velocity.vy_m_s};
    p.heading_rad = h.pose.theta_rad;
    p.radius_m = h.radius_m;
    const bool was = p.crossed.crossed;
    p.crossed = updateCrossed(p.crossed, h.pose, a.robot.pose.position(),
                              config_.crossed_hysteresis_m, config_.crossed_max_distance_m);
    p.last_seen_utime = a.utime;
    present_.touch(h.id, a.utime);
    heard_.touch(h.id, now);
    if (!was && p.crossed.crossed) crossed_now.insert(h.id);
  }
}

void Session::continueSwitchedIds(const SceneSnapshot& agents, SessionOutput& out) {
  std::set<std::int32_t> here;
  for (const auto& h : agents.humans) here.insert(h.id);
  std::vector<LostTrack> lost;
  for (const auto& [id, p] : people_) {
    // An ended interaction continues too: the person was told what it was told, and a new id
    // must not start round 1 again for someone who has already passed.
    if (!p.seen || here.count(id) || !p.decision) continue;
    lost.push_back({id, seconds(p.last_seen_utime), p.position_m, p.velocity_m_s});
  }
  TrackContinuityOptions options;
  options.max_gap_s = config_.human_gone_s;  // an absence this long ends the interaction anyway
  for (const auto& h : agents.humans) {
    if (lost.empty()) return;
    if (const auto it = people_.find(h.id);
        it != people_.end() && (it->second.seen || it->second.decision))
      continue;  // not a new id
    const auto old = continuedTrack(lost, seconds(agents.utime), h.pose.position(), options);
    if (!old) continue;
    Person moved = std::move(people_.at(*old));
    people_.erase(*old);
    // The new id may have a record of its own already (a path assessment, joined late).
    Person& p = people_[h.id];
    std::optional<StampedPath> own_path = p.path;
    const bool history_unknown = p.history_unknown;
    const bool judge_absence = p.judge_absence;
    p = std::move(moved);
    if (own_path) p.path = own_path;  // its own assessment is the newer one's
    p.history_unknown = p.history_unknown || history_unknown;
    p.judge_absence = p.judge_absence || judge_absence;
    present_.erase(*old);
    heard_.erase(*old);
    note(out, SessionNote::Level::kInfo,
         "human " + std::to_string(h.id) + " continues human " + std::to_string(*old) +
             " (a tracker id switch at utime " + std::to_string(agents.utime) +
             "): its interaction goes on, no round repeated");
    lost.erase(
        std::remove_if(lost.begin(), lost.end(), [&](const LostTrack& l) { return l.id == *old; }),
        lost.end());
  }
}

void Session::endAbsent(std::int64_t step, const SceneSnapshot& agents, SessionOutput& out) {
  const std::int64_t latest = *latest_agents_utime_;
  std::set<std::int32_t> gone;  // in id order: the order of the outputs
  while (const IdRecency::Entry* e = present_.oldest()) {
    if (diffSeconds(latest, e->utime) <= config_.human_gone_s) break;
    gone.insert(e->id);
    present_.erase(e->id);
  }
  // Humans whose decision began while they were already absent (the situation assessor still
  // reported someone the tracker had lost): judged now, as every absent human.
  for (auto& [id, p] : people_) {
    if (!p.judge_absence) continue;
    p.judge_absence = false;
    if (!present_.contains(id) && p.seen &&
        diffSeconds(latest, p.last_seen_utime) > config_.human_gone_s)
      gone.insert(id);
  }
  for (const std::int32_t id : gone) {
    Person& p = people_.at(id);
    if (!p.decision || p.decision->ended()) continue;
    const double absent_s = diffSeconds(latest, p.last_seen_utime);
    const std::string why = "human " + std::to_string(id) + " absent from the agent states for " +
                            fixed(absent_s, 1) + " s";
    const Stamp stamp{agents.utime, step, id};
    emit(stamp, p.decision->endInteraction(seconds(agents.utime), why), std::nullopt, out);
  }
}

void Session::forgetStale(const SessionInput& in, SessionOutput& out) {
  if (!in.clock_utime) return;
  const double max_age_s = std::max(forget_after_s_, config_.human_gone_s);
  std::vector<std::int32_t> forgotten;  // least recent first: the aged ones, then the others
  std::vector<std::int32_t> ended;      // of these, those whose interaction was still open
  const IdRecency::Forgotten n =
      heard_.forgetOld(*in.clock_utime, max_age_s, max_ids_, [&](std::int32_t id) {
        forgotten.push_back(id);
        const auto it = people_.find(id);
        if (it != people_.end() && it->second.decision && !it->second.decision->ended()) {
          // Never forgotten in the middle of it: the recorder is stopped and a dock resumed.
          ended.push_back(id);
          const Stamp stamp{in.utime, in.step, id};
          emit(stamp,
               it->second.decision->endInteraction(seconds(in.utime),
                                                   "forgotten (limits.max_ids / forget_after_s)"),
               std::nullopt, out, /*quiet=*/true);
        }
        forget(id);
      });
  if (forgotten.empty()) return;
  const auto aged_end = forgotten.begin() + static_cast<std::ptrdiff_t>(n.aged);
  note(out, SessionNote::Level::kInfo,
       "forgot " + std::to_string(n.aged) + " humans not heard of for " + fixed(max_age_s, 0) +
           " s (" + idList({forgotten.begin(), aged_end}) + ") and " + std::to_string(n.over) +
           " beyond limits.max_ids " + std::to_string(max_ids_) + " (" +
           idList({aged_end, forgotten.end()}) +
           "); interactions ended: " + (ended.empty() ? "-" : idList(ended)));
}

void Session::forget(std::int32_t id) {
  crowd_.forget(id);
  people_.erase(id);
  present_.erase(id);
  heard_.erase(id);
}

Session::Decided Session::decide(std::int64_t step, std::int32_t id, const Stamp& stamp,
                                 const SituationSnapshot& situation,
                                 std::optional<std::int64_t> clock_utime, SessionOutput& out) {
  heard_.touch(id, clock_utime.value_or(stamp.utime));
  Person& p = people_[id];
  // See joinLate: never a round or dock on a guess.
  if (p.history_unknown) return {stamp, {}, situation.t_cross_s};
  if (!p.decision) {
    p.decision.emplace(config_.decision);
    note(out, SessionNote::Level::kInfo,
         "human " + std::to_string(id) + " seen first at step " + std::to_string(step) +
             " (t_cross " + formatTCross(situation.t_cross_s) + ")");
    if (p.seen && !present_.contains(id)) p.judge_absence = true;
  }
  p.last_situation = situation;
  DecisionInput in;
  in.t_s = seconds(stamp.utime);
  in.situation = situation;
  if (p.path) {
    const double age_s = diffSeconds(stamp.utime, p.path->utime);
    if (age_s <= config_.path_max_age_s) {
      in.path = p.path->snapshot;
    } else if (p.stale_path_logged_utime != p.path->utime) {
      p.stale_path_logged_utime = p.path->utime;  // once per stale assessment
      note(out, SessionNote::Level::kWarn,
           "step " + std::to_string(stamp.step) + " human " + std::to_string(id) +
               ": the latest path assessment is " + fixed(age_s, 1) +
               " s old (over path_max_age_s " + fixed(config_.path_max_age_s, 1) +
               " s): CM and IsContributing unknown");
    }
  }
  in.crossed = p.seen && p.crossed.crossed;
  in.heard_by_s = p.heard_by_s;
  if (p.seen && present_.contains(id) && robot_known_) {
    // The stand-off watch sees the robot and this person as the latest agent states have them.
    StandOffInput m;
    m.t_s = in.t_s;
    m.robot_speed_m_s = robot_speed_m_s_;
    m.human_speed_m_s = p.velocity_m_s.norm();
    m.centre_distance_m = (p.position_m - robot_pose_.position()).norm();
    m.gap_m = m.centre_distance_m - robot_radius_m_ - p.radius_m;
    if (m.centre_distance_m > 0.0) {
      const Eigen::Vector2d away = (robot_pose_.position() - p.position_m) / m.centre_distance_m;
      m.robot_receding_m_s = robot_velocity_m_s_.dot(away);
      m.human_closing_m_s = p.velocity_m_s.dot(away);
      m.human_ahead = -away.dot(headingVector(robot_pose_.theta_rad)) > 0.0;
    }
    m.t_cross_s = situation.t_cross_s;
    in.motion = m;
  }
  // A person ahead walking the robot's way is followed, then passed with words
  // (overtake_words.hpp), not met as the flowchart's oncoming person; from the words on until
  // the pass is done. No deadline: the words are said before the robot speeds up to pass.
  if (config_.overtake.enabled && in.motion && !p.decision->roundFired(1)) {
    AgentState h;
    h.id = id;
    h.pose = {p.position_m.x(), p.position_m.y(), p.heading_rad};
    h.velocity = {p.velocity_m_s.x(), p.velocity_m_s.y(), 0.0};
    h.radius_m = p.radius_m;
    OvertakeWords::Input o;
    o.t_s = in.t_s;
    o.t_cross_s = situation.t_cross_s;
    o.person = sameWayAhead(robot_pose_, robot_radius_m_, {h}, config_.overtake.same_way);
    o.robot_radius_m = robot_radius_m_;
    o.heard_by_s = p.heard_by_s;
    o.muted = config_.muted;
    for (const auto& [other_id, other] : people_)
      if (other.decision && (other.decision->docked() || other.last_situation.robot_retreating))
        o.robot_making_room = true;
    if (o.person || p.overtake.engaged())
      return {stamp, p.overtake.step(o, config_.overtake, config_.decision.templates),
              std::nullopt};
  }
  const DecisionOutput decided = p.decision->step(in);
  for (const auto& r : decided.rounds)
    if (r.round == 2 && !r.deferred)
      note(out, SessionNote::Level::kInfo,
           "step " + std::to_string(stamp.step) + " human " + std::to_string(id) +
               " round 2 on CM " + formatOptional(in.path.cm_window_m) + " m against d_h " +
               formatOptional(situation.d_h_m) + " m, IsContributing " +
               tristateName(in.path.is_contributing) + ", p_contributing " +
               formatOptional(in.path.p_contributing) + ", RobotIsConstrained " +
               tristateName(situation.robot_is_constrained) +
               (p.heard_by_s
                    ? " (" + fixed(in.t_s - *p.heard_by_s, 2) + " s after round 1's words ended)"
                    : std::string()));
  return {stamp, decided, situation.t_cross_s};
}

void Session::emitDecided(std::vector<Decided>& decided, SessionOutput& out) {
  // Every utterance of the step, tagged with its place in this list.
  std::vector<std::pair<std::size_t, std::size_t>> where;  // (decision, utterance)
  std::vector<DecidedUtterance> utterances;
  for (std::size_t i = 0; i < decided.size(); ++i)
    for (std::size_t k = 0; k < decided[i].out.utterances.size(); ++k) {
      utterances.push_back({decided[i].stamp.human_id, decided[i].out.utterances[k], where.size()});
      where.emplace_back(i, k);
    }
  std::vector<CoordinatedUtterance> coordinated;
  if (!utterances.empty()) {
    std::vector<CrowdMember> scene;
    bool making_room = false;
    for (const auto& [id, p] : people_) {
      if (p.seen && present_.contains(id)) scene.push_back({id, p.position_m, p.velocity_m_s});
      if (p.decision)
        making_room = making_room || p.decision->docked() || p.last_situation.robot_retreating;
    }
    coordinated = crowd_.coordinate(robot_pose_, scene, std::move(utterances), making_room);
  }
  std::vector<std::vector<const CoordinatedUtterance*>> mine(decided.size());
  for (std::size_t i = 0; i < decided.size(); ++i) mine[i].resize(decided[i].out.utterances.size());
  for (const auto& c : coordinated) mine[where[c.tag].first][where[c.tag].second] = &c;
  for (std::size_t i = 0; i < decided.size(); ++i)
    emit(decided[i].stamp, decided[i].out, decided[i].t_cross_s, out, false, &mine[i]);
}

// ---- output ----

void Session::emit(const Stamp& stamp, const DecisionOutput& decision,
                   std::optional<double> t_cross_s, SessionOutput& out, bool quiet,
                   const std::vector<const CoordinatedUtterance*>* coordinated) {
  const std::string who = "human " + std::to_string(stamp.human_id);
  std::string why;
  for (const auto& r : decision.rounds) {
    if (!quiet)
      note(out, r.degraded ? SessionNote::Level::kWarn : SessionNote::Level::kInfo,
           "step " + std::to_string(stamp.step) + " " + who + " round " + std::to_string(r.round) +
               (r.deferred ? " deferred" : "") + " (t_cross " + formatTCross(r.t_cross_s) +
               "): " + r.branch + (r.reason.empty() ? "" : "; ") + r.reason);
    if (why.empty())
      why =
          (r.round > 0 ? "round " + std::to_string(r.round) + (r.deferred ? " deferred" : "") + ": "
                       : std::string()) +
          r.branch + (r.reason.empty() ? "" : " (" + r.reason + ")");
  }
  // Order of docs/lockstep.md row 4: utterances, robot actions, recorder controls.
  const double t_s = seconds(stamp.utime);
  for (std::size_t k = 0; k < decision.utterances.size(); ++k) {
    const CoordinatedUtterance* c =
        coordinated && k < coordinated->size() ? (*coordinated)[k] : nullptr;
    Utterance u = c ? c->utterance : decision.utterances[k];
    const std::vector<std::int32_t> group = c ? c->group : std::vector<std::int32_t>{};
    const std::optional<double> t = u.round == 3 ? std::nullopt : t_cross_s;
    const std::string what =
        "\"" + u.text + "\" (" + toString(u.act) + ", round " + std::to_string(u.round);
    // Words that decide a stand-off have no crossing to be late for: nobody is going yet.
    const bool has_deadline = !endsStandOff(u.act) && !u.resolves_stand_off;
    if (c && c->verdict != CrowdVerdict::kSay) {
      // Decided, not said (crowd.hpp): published all the same, as every decided utterance is.
      SpeechSlot slot;
      slot.delivery = c->verdict == CrowdVerdict::kToldToGroup ? Delivery::kToldToGroup
                                                               : Delivery::kContradicts;
      slot.duration_s = 0.0;
      out.messages.emplace_back(UtteranceOut{stamp, u, t, slot, group});
      note(out, SessionNote::Level::kInfo, "not said to " + who + ": " + what + "): " + c->reason);
      continue;
    }
    // A cue is worth saying only if its words end before the crossing; thanks have no deadline.
    const std::optional<double> deadline_s =
        has_deadline && t && std::isfinite(*t) ? std::optional<double>(t_s + *t) : std::nullopt;
    // Short of time, a making-room sentence is said in its shorter wording rather than not at all.
    const std::vector<std::string> texts = wordings(config_.decision.templates, u);
    std::vector<double> durations_s;
    durations_s.reserve(texts.size());
    for (const auto& w : texts) durations_s.push_back(speechDuration(w));
    const double free_in_s = std::max(0.0, voice_.freeAt() - t_s);
    // Words announcing that the robot makes room, or goes first, change what the person was
    // told: they cut the words being said rather than be lost behind them.
    const bool changes_action =
        config_.interrupt_for_change && (announcesMakingRoom(u.act) || endsStandOff(u.act));
    const auto choice =
        voice_.planFirstFitting(t_s, durations_s, deadline_s, config_.muted, changes_action);
    const SpeechSlot slot = choice.slot;
    if (slot.interrupts_s > 0.0) {
      note(out, SessionNote::Level::kInfo,
           "to " + who + ": \"" + texts[choice.index] + "\" interrupts the words being said (" +
               fixed(slot.interrupts_s, 2) + " s before their end)");
    }
    if (choice.index > 0) {
      note(out, SessionNote::Level::kInfo,
           "to " + who + ": \"" + u.text + "\" (" + fixed(durations_s[0], 2) + " s) would end " +
               fixed(t_s + free_in_s + durations_s[0] - deadline_s.value_or(t_s), 2) +
               " s after the crossing: said as \"" + texts[choice.index] + "\"");
      u.text = texts[choice.index];
    }
    out.messages.emplace_back(UtteranceOut{stamp, u, t, slot, group});
    switch (slot.delivery) {
      case Delivery::kToldToGroup:
      case Delivery::kContradicts:
        break;  // never planned by the voice
      case Delivery::kSaid:
        // The group hears it too: its round 2 judges them from when the words ended.
        for (const std::int32_t id : group)
          if (const auto p = people_.find(id); p != people_.end() && p->second.decision)
            p->second.heard_by_s = t_s + slot.end_s();
        if (const auto p = people_.find(stamp.human_id); p != people_.end() && p->second.decision)
          p->second.heard_by_s = t_s + slot.end_s();
        note(out, SessionNote::Level::kInfo,
             "to " + who + ": \"" + u.text + "\" (" + toString(u.act) + ", round " +
                 std::to_string(u.round) + "; " + fixed(slot.duration_s, 2) + " s" +
                 (slot.start_s > 0.0 ? ", after " + fixed(slot.start_s, 2) + " s" : "") + ")");
        out.speak.push_back({u.text, "u" + std::to_string(stamp.utime) + "_h" +
                                         std::to_string(stamp.human_id) + "_r" +
                                         std::to_string(u.round) + "_" + toString(u.act)});
        break;
      case Delivery::kMuted:
        note(out, SessionNote::Level::kInfo,
             "muted: not said to " + who + ": \"" + u.text + "\" (" + toString(u.act) + ", round " +
                 std::to_string(u.round) + ")");
        break;
      case Delivery::kTooLate:
        note(out, SessionNote::Level::kInfo,
             "not said to " + who + ": \"" + u.text + "\" (" + toString(u.act) + ", round " +
                 std::to_string(u.round) + "): its " + fixed(slot.duration_s, 2) +
                 " s of speech would end " +
                 fixed(t_s + slot.end_s() - deadline_s.value_or(t_s), 2) + " s after the crossing");
        break;
    }
  }
  for (const auto a : decision.robot_actions) {
    out.messages.emplace_back(RobotActionOut{stamp, a, why});
    note(out, SessionNote::Level::kInfo,
         std::string("robot action ") + toString(a) + " for " + who);
  }
  for (const auto c : decision.recorder_commands) {
    const bool start = c == RecorderCommand::kStart;
    out.messages.emplace_back(RecorderOut{stamp, c, why,
                                          start ? decision.start_d_oh_m : std::nullopt,
                                          start ? decision.start_d_h_m : std::nullopt});
    note(out, SessionNote::Level::kDebug, std::string("recorder ") + toString(c) + " for " + who);
  }
}

}  // namespace coopnav::dialogue
