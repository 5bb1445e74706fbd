#pragma once
/// @file The lifecycle every coopnav daemon shares: LCM construction with a provider check,
/// a poll loop on the LCM fd plus a signal self-pipe, clean exit on SIGINT/SIGTERM, a status
/// message once a second (and at once to a peer heard for the first time, so that a process
/// started later, e.g. the world waiting for its participants, need not wait a period), safe
/// decoding with counters, and lockstep step acknowledgements.
///
/// Time: the logic of a daemon runs on message utime only. The runtime's own timers (status,
/// request timeouts) use the monotonic clock: they are about liveness, never about decisions.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "coopnav/channels.hpp"
#include "runtime/limits.hpp"

struct pollfd;  // <poll.h>

namespace coopnav {

class step_ack_t;

/// Thrown when LCM cannot be used (bad URL, no multicast route, self-test failure).
class LcmUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Thrown by a message handler to reject a message (bad content); counted, logged, dropped.
class RejectedMessage : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Thrown by a message handler for a well-formed message it cannot use (stale, unknown id).
class DroppedMessage : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Process exit codes, documented in every daemon's --help.
enum ExitCode : int {
  kExitOk = 0,        ///< clean stop on SIGINT/SIGTERM
  kExitRuntime = 1,   ///< LCM unavailable or an unexpected failure
  kExitUsage = 2,     ///< bad command line or config
  kExitBadInput = 3,  ///< bad map or scenario file
};

struct RuntimeCounters {
  std::int64_t received{0};
  std::int64_t dropped{0};
  std::int64_t rejected{0};
  std::int64_t published{0};
};

class Runtime {
 public:
  /// Opens LCM at `lcm_url` ("" = $LCM_DEFAULT_URL or LCM's default) and checks the provider:
  /// Debian's LCM 1.3.1 otherwise aborts later inside handleTimeout. Throws LcmUnavailable.
  /// Every runtime of a process opened on "memq://" shares one in-process bus (LCM's memq delivers
  /// only within one instance): nodes and probes of an in-process test talk as over udpm, and
  /// any one of them spinning handles the messages of all.
  Runtime(std::string name, const std::string& lcm_url);
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

  const std::string& name() const { return name_; }

  /// The caps of this daemon (its config's `limits`; the defaults until set).
  const InputLimits& limits() const { return limits_; }
  /// Sets the caps, the log's included (log.hpp).
  void setLimits(const InputLimits& limits);
  lcm::LCM& lcm() { return *lcm_; }

  /// Subscribes with safe decoding: a message that fails to decode (wrong type on the channel,
  /// truncated, corrupt count) is counted as rejected and logged, never crashes the daemon.
  /// The handler may throw RejectedMessage or DroppedMessage to have the message counted so.
  /// Received messages wait in the subscription's own bounded queue until handled, oldest of the
  /// process first: at most `queue_capacity` messages (0 = limits.queue_messages) and
  /// limits.queue_mib; beyond either the oldest waiting one of the channel is dropped, counted in
  /// `dropped` and named in a log line at the next status (limits.hpp says why the oldest).
  /// `journaled` = false keeps the channel out of the restart journal (journal.hpp): inputs
  /// that are answers to this process's own requests, or that it may recompute on demand.
  template <class Msg>
  void subscribe(const std::string& channel,
                 std::function<void(const Msg&, std::int64_t recv_utime)> handler,
                 int queue_capacity = 0, bool journaled = true);

  /// Encodes and publishes; counts it. Returns false (and logs) on a publish failure.
  template <class Msg>
  bool publish(const std::string& channel, const Msg& msg);

  /// Publishes already encoded bytes (a cached output sent again); counts it.
  bool publishRaw(const std::string& channel, const std::vector<std::uint8_t>& bytes);

  /// Publishes a lockstep acknowledgement of step `step` stamped `utime` (no output counts: a
  /// node that publishes per-step outputs acknowledges through StepOutputs instead).
  void ackStep(std::int64_t utime, std::int64_t step);

  /// Fills an acknowledgement's restart fields, and notes the first step acknowledged live.
  void fillRestart(step_ack_t& ack);

  // ---- restarts (journal.hpp, docs/lockstep.md "Loss and restarts") ----
  /// While muted (replaying the journal) nothing is sent and no timer runs.
  void setMuted(bool muted) { muted_ = muted; }
  bool muted() const { return muted_; }
  /// Called with every message received on a journaled channel, before it is handled.
  using ReceiveHook = std::function<void(const std::string& channel, const void* data,
                                         std::size_t size, std::int64_t recv_utime)>;
  void setReceiveHook(ReceiveHook hook) { receive_hook_ = std::move(hook); }
  /// Hands a recorded message to the subscriptions of `channel`, as if just received.
  void dispatchRaw(const std::string& channel, const void* data, std::size_t size,
                   std::int64_t recv_utime);
  /// This process restarted mid-run: `recovered` (state rebuilt from the journal) or not; the
  /// note says what was recovered or lost. Reported in every later ack and in the status.
  void setRestarted(bool recovered, const std::string& note);
  /// What a restart without its state loses (the node says; used when it joins mid-run).
  void setLostStateNote(const std::string& note) { lost_state_note_ = note; }
  /// Notes an ack of the world simulator (the step gates call this). The first one heard tells
  /// whether this process was there when the run started (step -1 "here" acks, or step 0) or
  /// joined it later: a restart without its journal, which then says so in its acks.
  void noteWorldAck(std::int64_t step) {
    if (!world_heard_) first_world_ack_step_ = step;
    world_heard_ = true;
  }
  /// Heard the world first after its step 0 (and rebuilt nothing from a journal).
  bool joinedLate() const { return world_heard_ && first_world_ack_step_ > 0 && !recovered_; }

  /// Runs `fn` every `period` of monotonic time from the loop (liveness work only).
  void addTimer(std::chrono::milliseconds period, std::function<void()> fn);
  /// Runs `fn` from the loop (run() and spinFor()) whenever `fd` is readable: an input that is
  /// not LCM wakes the loop itself (the ROS 2 bridge's DDS listener writes a self-pipe), so its
  /// handlers run on the loop's thread like every other. `fn` must read what made fd readable.
  /// The fd stays the caller's (it must outlive this runtime's loop).
  void addReadable(int fd, std::function<void()> fn);
  /// poll()'s timeout [ms] for the next timer due in `until_due`: rounded up to whole
  /// milliseconds (0 only when due), so that the loop sleeps until the timer is due instead of
  /// polling without a timeout through the last fraction of a millisecond; at most 1000.
  static int pollTimeoutMs(std::chrono::steady_clock::duration until_due);

  /// Sets the state and the free-text detail reported in the status message.
  void setDegraded(const std::string& detail);
  void setRunning(const std::string& detail = "");

  /// The state and detail the next status message reports (daemon_status_t::STATE_*).
  std::int8_t state() const { return state_; }
  const std::string& detail() const { return detail_; }

  /// Records the message time of the latest input processed (reported in the status).
  void noteLogicTime(std::int64_t utime) { last_logic_utime_ = utime; }

  /// Handles messages for up to `timeout_ms` (0 = only what is pending); runs due timers.
  /// Returns the number of messages handled. For tests and single-threaded clients.
  int spinFor(int timeout_ms);

  /// The daemon loop: until SIGINT/SIGTERM (or requestStop), handle messages, run timers,
  /// publish status once a second. Returns kExitOk on a clean stop.
  int run();

  /// Asks run() to return (thread-safe and async-signal-safe).
  void requestStop();

  const RuntimeCounters& counters() const { return counters_; }
  /// Messages received and waiting to be handled, over every subscription of this process's bus.
  std::size_t queued() const;
  /// Messages of `channel` dropped from its full queue since this runtime started.
  std::int64_t queueDropped(const std::string& channel) const;
  void countDropped() { ++counters_.dropped; }
  void countRejected() { ++counters_.rejected; }

  /// Installs the stop handlers (SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGUSR2: each a clean stop)
  /// writing to a process-wide self-pipe (idempotent).
  static void installSignalHandlers();
  /// From now until the first run(), a stop signal ends the process at once with exit 0 and a
  /// line on stderr: start-up (reading a map, replaying a journal) holds no state worth saving,
  /// and a stop must be answered within a second whatever it is doing.
  static void beginStartup();
  /// True once a stop signal arrived (async-signal-safe flag, read between messages).
  static bool stopSignalled();

 private:
  struct Subscription;
  struct Inbox;
  struct Timer {
    std::chrono::milliseconds period;
    std::chrono::steady_clock::time_point next;
    std::function<void()> fn;
  };
  void dispatch(const std::function<void()>& body, const std::string& channel);
  /// Another process of this daemon's name on the bus (its status messages): DEGRADED while heard.
  /// A peer heard for the first time is answered with this daemon's status at once, once the
  /// daemon is up (not STARTING): answerNewPeers, after each wake-up's messages are moved.
  void onPeerStatus(const void* data, std::size_t size);
  void answerNewPeers();
  void checkDuplicate();
  void publishStatus();
  void runDueTimers();
  int msUntilNextTimer() const;
  /// Moves what LCM received into the subscriptions' queues (a copy each), at most `budget`.
  int pump(int budget);
  /// Handles the oldest waiting message of the bus (any runtime's); false when none waits.
  bool handleNext();
  void registerSubscription(Subscription* sub);
  void reportQueueDrops();

  std::string name_;
  InputLimits limits_;
  std::shared_ptr<lcm::LCM> lcm_;
  std::shared_ptr<Inbox> inbox_;  ///< shared by every runtime on lcm_ (memq://)
  std::vector<std::unique_ptr<Subscription>> subscriptions_;
  std::vector<Timer> timers_;
  struct Readable {
    int fd;
    std::function<void()> fn;
  };
  std::vector<Readable> readables_;
  /// Runs the handler of each of readables_ whose pollfd (`fds`, one per readable, in order)
  /// poll() found readable.
  void runReadables(const ::pollfd* fds);
  RuntimeCounters counters_;
  std::int8_t state_{0};
  std::string detail_;
  std::int64_t last_logic_utime_{-1};
  std::vector<double> cycle_ms_;
  int max_backlog_{0};  ///< most messages waiting at one wake-up since the last status
  std::atomic<bool> stop_{false};
  int stop_pipe_[2]{-1, -1};
  bool muted_{false};
  ReceiveHook receive_hook_;
  std::int8_t restart_{0};
  std::int64_t restart_step_{-1};
  bool restart_decided_{false};
  bool recovered_{false};
  bool world_heard_{false};
  std::int64_t first_world_ack_step_{-1};
  std::string restart_note_;
  std::string lost_state_note_{"its state"};
  lcm::Subscription* status_sub_{nullptr};
  std::int32_t duplicate_pid_{0};  ///< 0: no other process of this name heard
  std::chrono::steady_clock::time_point duplicate_heard_{};
  std::string duplicate_detail_;
  /// Peers whose status was heard (answered once each, at most kMaxPeersAnswered names).
  std::set<std::string> peers_heard_;
  bool answer_status_{false};  ///< a new peer was heard: publish the status now
};

/// Decodes one received payload as Msg the way every subscription does: a payload that does not
/// decode (wrong type, truncated, negative count), or has bytes left over, throws RejectedMessage.
/// Public so that the fuzzers (test/fuzz) drive exactly the daemons' decoding.
template <class Msg>
void decodeOrReject(const void* data, std::size_t size, Msg& msg);

// ---- template implementation ----

template <class Msg>
void decodeOrReject(const void* data, std::size_t size, Msg& msg) {
  // LCM's decoders take an int length; a bigger payload cannot be a message of ours (2^28 max).
  if (size > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw RejectedMessage("payload too large for " + std::string(Msg::getTypeName()));
  // The generated decoder may throw (std::length_error on a negative count) or fail.
  int used = -1;
  try {
    used = msg.decode(data, 0, static_cast<int>(size));
  } catch (const std::exception& e) {
    throw RejectedMessage(std::string("decode threw: ") + e.what());
  }
  if (used < 0) throw RejectedMessage("cannot decode as " + std::string(Msg::getTypeName()));
  if (used != static_cast<int>(size))
    throw RejectedMessage("trailing bytes after " + std::string(Msg::getTypeName()));
}

struct Runtime::Subscription {
  struct Waiting {
    std::vector<std::uint8_t> bytes;
    std::int64_t recv_utime;
    std::uint64_t seq;  ///< arrival order over the whole bus
  };
  Runtime* runtime{nullptr};
  std::string channel;
  std::function<void(const lcm::ReceiveBuffer*)> on_message;
  lcm::Subscription* handle{nullptr};
  bool journaled{true};
  int capacity{0};  ///< messages; 0 = the runtime's limits.queue_messages
  std::deque<Waiting> queue;
  std::size_t queued_bytes{0};
  std::size_t largest_bytes{0};  ///< largest message seen: sizes LCM's own queue (runtime.cpp)
  int lcm_capacity{-1};
  std::int64_t dropped{0};  ///< since the start
  std::int64_t dropped_unreported{0};
  /// Queues a received message, dropping the oldest waiting ones beyond the caps.
  void enqueue(const lcm::ReceiveBuffer* rbuf);
  /// Sizes LCM's own queue of this subscription from the caps and the largest message seen.
  void syncLcmCapacity();
  // A plain function with a context pointer (LCM's subscribeFunction), not a member function:
  // LCM's member-function wrapper calls `(subs->handler->*subs->handlerMethod)(...)`, and GCC 12's
  // -fsanitize=vptr checks an uninitialised temporary in that expression, so every message would
  // abort a UBSan build (a compiler bug, reproduced without LCM; clang is clean; see
  // docs/sanitizers.md).
  static void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string&, Subscription* self) {
    self->enqueue(rbuf);
  }
  /// Hands the oldest waiting message to the journal hook and the handler.
  void handleFront();
};

template <class Msg>
void Runtime::subscribe(const std::string& channel,
                        std::function<void(const Msg&, std::int64_t)> handler, int queue_capacity,
                        bool journaled) {
  auto sub = std::make_unique<Subscription>();
  sub->runtime = this;
  sub->channel = channel;
  sub->journaled = journaled;
  sub->on_message = [this, channel, handler](const lcm::ReceiveBuffer* rbuf) {
    dispatch(
        [&] {
          Msg msg;
          decodeOrReject(rbuf->data, rbuf->data_size, msg);
          handler(msg, rbuf->recv_utime);
        },
        channel);
  };
  // Channel names are anchored GLib regexes in LCM: escape nothing, ours are plain UPPER_SNAKE.
  sub->capacity = std::max(0, queue_capacity);
  sub->handle = lcm_->subscribeFunction(channel, &Subscription::onMessage, sub.get());
  registerSubscription(sub.get());
  subscriptions_.push_back(std::move(sub));
}

template <class Msg>
bool Runtime::publish(const std::string& channel, const Msg& msg) {
  if (muted_) return true;
  if (lcm_->publish(channel, &msg) != 0) return false;
  ++counters_.published;
  return true;
}

}  // namespace coopnav
