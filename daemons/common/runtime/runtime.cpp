#include "runtime/runtime.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <vector>

#include "coopnav/daemon_status_t.hpp"
#include "coopnav/step_ack_t.hpp"
#include "runtime/log.hpp"

namespace coopnav {
namespace {

// One self-pipe per process: a signal handler may only write(2) and set lock-free atomics.
int g_signal_pipe[2] = {-1, -1};
std::atomic<bool> g_signalled{false};
std::atomic<bool> g_starting{false};
static_assert(std::atomic<bool>::is_always_lock_free, "a signal handler may set it");

void onSignal(int) {
  const int saved = errno;
  if (g_starting.load()) {
    static const char kLine[] = "coopnav: stop signal during start-up: exiting\n";
    [[maybe_unused]] auto w = ::write(STDERR_FILENO, kLine, sizeof kLine - 1);
    ::_exit(0);
  }
  g_signalled.store(true);
  const char c = 's';
  if (g_signal_pipe[1] >= 0) [[maybe_unused]]
    auto n = ::write(g_signal_pipe[1], &c, 1);
  errno = saved;
}

std::int64_t wallUtime() {
  // Status messages report process health: wall time is right here, and only here.
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

void makePipe(int fds[2]) {
  if (::pipe(fds) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  for (int i = 0; i < 2; ++i) {
    ::fcntl(fds[i], F_SETFL, ::fcntl(fds[i], F_GETFL) | O_NONBLOCK);
    ::fcntl(fds[i], F_SETFD, FD_CLOEXEC);
  }
}

}  // namespace

void Runtime::installSignalHandlers() {
  if (g_signal_pipe[0] >= 0) return;
  makePipe(g_signal_pipe);
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: poll() returns EINTR and we look at the pipe at once
  // SIGHUP (the terminal went away, or "reload" by habit) and the user signals stop cleanly too:
  // their default would kill the daemon without its final status.
  for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGUSR2}) sigaction(sig, &sa, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
}

void Runtime::beginStartup() {
  installSignalHandlers();
  g_starting.store(true);
}

bool Runtime::stopSignalled() { return g_signalled.load(); }

void Runtime::setLimits(const InputLimits& limits) {
  limits_ = limits;
  for (auto& s : subscriptions_) s->syncLcmCapacity();
  setLogCaps(static_cast<std::size_t>(limits.max_text_bytes), limits.log_lines_per_s);
}

/// The messages received on one LCM instance and not yet handled, over the subscriptions of every
/// runtime using it: handled oldest first, whichever runtime spins (memq:// is shared).
struct Runtime::Inbox {
  std::vector<Subscription*> subs;
  std::uint64_t next_seq{0};
  std::size_t waiting{0};
};

namespace {

/// [messages] What one wake-up moves from LCM into the queues before handling the next message:
/// a copy each, so that LCM's own queue stays short however slow a handler is.
constexpr int kPumpBudget = 10000;
// Peers a daemon answers the first status of (a run has seven processes; a busy bus a few more).
constexpr std::size_t kMaxPeersAnswered = 64;

}  // namespace

void Runtime::Subscription::enqueue(const lcm::ReceiveBuffer* rbuf) {
  Runtime& rt = *runtime;
  Inbox& inbox = *rt.inbox_;
  const std::size_t max_messages =
      static_cast<std::size_t>(capacity > 0 ? capacity : rt.limits_.queue_messages);
  const std::size_t max_bytes = rt.limits_.queueBytes();
  const std::size_t size = rbuf->data_size;
  while (!queue.empty() && (queue.size() >= max_messages || queued_bytes + size > max_bytes)) {
    queued_bytes -= queue.front().bytes.size();
    queue.pop_front();
    --inbox.waiting;
    ++dropped;
    ++dropped_unreported;
    ++rt.counters_.dropped;
  }
  const auto* bytes = static_cast<const std::uint8_t*>(rbuf->data);
  queue.push_back(
      {std::vector<std::uint8_t>(bytes, bytes + size), rbuf->recv_utime, inbox.next_seq++});
  queued_bytes += size;
  ++inbox.waiting;
  largest_bytes = std::max(largest_bytes, size);
  syncLcmCapacity();
}

void Runtime::Subscription::syncLcmCapacity() {
  // LCM's own per-subscription queue (between its receive thread and the copy into ours) holds
  // what arrives while a handler runs: bounded as ours, in messages of the largest size seen, so
  // that it cannot hold more bytes than the caps either. Its drops (the newest) are those of a
  // lost datagram: a lockstep step is then re-published (docs/lockstep.md). Set from the start:
  // LCM's default (30) would cut a burst before the first message is handled.
  const InputLimits& limits = runtime->limits_;
  const std::size_t max_messages =
      static_cast<std::size_t>(capacity > 0 ? capacity : limits.queue_messages);
  const int lcm_cap = static_cast<int>(std::clamp<std::size_t>(
      limits.queueBytes() / std::max<std::size_t>(largest_bytes, 1), 1, max_messages));
  if (lcm_cap != lcm_capacity && handle) {
    handle->setQueueCapacity(lcm_cap);  // never 0: LCM reads 0 as unlimited
    lcm_capacity = lcm_cap;
  }
}

void Runtime::Subscription::handleFront() {
  Waiting w = std::move(queue.front());
  queue.pop_front();
  queued_bytes -= w.bytes.size();
  --runtime->inbox_->waiting;
  if (journaled && runtime->receive_hook_)
    runtime->receive_hook_(channel, w.bytes.data(), w.bytes.size(), w.recv_utime);
  lcm::ReceiveBuffer rbuf{};
  rbuf.data = w.bytes.data();
  rbuf.data_size = static_cast<std::uint32_t>(w.bytes.size());
  rbuf.recv_utime = w.recv_utime;
  on_message(&rbuf);
}

Runtime::Runtime(std::string name, const std::string& lcm_url) : name_(std::move(name)) {
  if (lcm_url.rfind("memq://", 0) == 0) {
    // One in-process bus per process: runtimes come and go, the bus lives while any uses it.
    static std::weak_ptr<lcm::LCM> shared;
    static std::weak_ptr<Inbox> shared_inbox;
    lcm_ = shared.lock();
    inbox_ = shared_inbox.lock();
    if (!lcm_ || !inbox_) {
      lcm_ = std::make_shared<lcm::LCM>(lcm_url);
      inbox_ = std::make_shared<Inbox>();
      shared = lcm_;
      shared_inbox = inbox_;
    }
  } else {
    lcm_ = std::make_shared<lcm::LCM>(lcm_url);
    inbox_ = std::make_shared<Inbox>();
  }
  // LCM 1.3.1 ignores a failed provider/self-test until handleTimeout aborts on fd -1.
  if (!lcm_->good() || lcm_->getFileno() < 0) {
    throw LcmUnavailable("LCM provider '" + (lcm_url.empty() ? std::string("default") : lcm_url) +
                         "' is not usable (bad URL, no multicast route on lo, or self-test "
                         "failure; see README 'Troubleshooting')");
  }
  makePipe(stop_pipe_);
  state_ = daemon_status_t::STATE_STARTING;
  // Not through subscribe(): peers' status is no input of the daemon (not counted, journaled
  // or rejected), only a check that this name runs once on the bus.
  status_sub_ = lcm_->subscribeFunction(
      channels::kStatus,
      +[](const lcm::ReceiveBuffer* rbuf, const std::string&, Runtime* self) {
        self->onPeerStatus(rbuf->data, rbuf->data_size);
      },
      this);
}

void Runtime::onPeerStatus(const void* data, std::size_t size) {
  daemon_status_t s;
  try {
    decodeOrReject(data, size, s);
  } catch (const RejectedMessage&) {
    return;  // somebody else's problem: the daemons that consume status count it
  }
  // A process that just started (the world waiting for its participants' status, a launcher's
  // wait-ready) learns that this one is up at once, not up to a status period later. Once per
  // name, and for a bounded number of names: a flood of invented names is no flood of answers.
  if (state_ != daemon_status_t::STATE_STARTING && s.name != name_ &&
      s.state != daemon_status_t::STATE_STOPPING && peers_heard_.size() < kMaxPeersAnswered &&
      peers_heard_.insert(s.name).second)
    answer_status_ = true;
  if (s.name != name_ || s.pid == static_cast<std::int32_t>(::getpid()) ||
      s.state == daemon_status_t::STATE_STOPPING)
    return;
  duplicate_heard_ = std::chrono::steady_clock::now();
  if (duplicate_pid_ == s.pid) return;
  duplicate_pid_ = s.pid;
  // Both go on: stopping either would leave the run without it if the other is the one that
  // dies next; the operator sees it in both statuses and logs.
  duplicate_detail_ = "another " + name_ + " runs on this bus (pid " + std::to_string(s.pid) +
                      "): every input is handled twice";
  setDegraded(duplicate_detail_);
}

void Runtime::answerNewPeers() {
  if (!answer_status_) return;
  answer_status_ = false;
  if (!muted_) publishStatus();
}

void Runtime::checkDuplicate() {
  if (duplicate_pid_ == 0) return;
  if (std::chrono::steady_clock::now() - duplicate_heard_ < std::chrono::seconds(3)) return;
  log().info("{}: pid {} of the same name is no longer heard", name_, duplicate_pid_);
  duplicate_pid_ = 0;
  if (state_ == daemon_status_t::STATE_DEGRADED && detail_ == duplicate_detail_) setRunning();
}

Runtime::~Runtime() {
  if (status_sub_) lcm_->unsubscribe(status_sub_);
  for (auto& s : subscriptions_) {
    if (s->handle) lcm_->unsubscribe(s->handle);
    inbox_->waiting -= s->queue.size();
    auto& subs = inbox_->subs;
    subs.erase(std::remove(subs.begin(), subs.end(), s.get()), subs.end());
  }
  for (int fd : stop_pipe_)
    if (fd >= 0) ::close(fd);
}

void Runtime::registerSubscription(Subscription* sub) {
  inbox_->subs.push_back(sub);
  sub->syncLcmCapacity();
}

std::size_t Runtime::queued() const { return inbox_->waiting; }

std::int64_t Runtime::queueDropped(const std::string& channel) const {
  std::int64_t n = 0;
  for (const auto& s : subscriptions_)
    if (s->channel == channel) n += s->dropped;
  return n;
}

int Runtime::pump(int budget) {
  int n = 0;
  while (n < budget && lcm_->handleTimeout(0) > 0) ++n;
  return n;
}

bool Runtime::handleNext() {
  if (inbox_->waiting == 0) return false;
  Subscription* oldest = nullptr;
  for (Subscription* s : inbox_->subs)
    if (!s->queue.empty() && (!oldest || s->queue.front().seq < oldest->queue.front().seq))
      oldest = s;
  if (!oldest) return false;
  oldest->handleFront();
  return true;
}

void Runtime::reportQueueDrops() {
  for (auto& s : subscriptions_) {
    if (s->dropped_unreported == 0) continue;
    const int cap = s->capacity > 0 ? s->capacity : limits_.queue_messages;
    log().warn(
        "{}: dropped the oldest {} waiting messages of {} in the last second: its queue was full "
        "({} messages or {} MiB; limits.queue_messages, limits.queue_mib)",
        name_, s->dropped_unreported, s->channel, cap, limits_.queue_mib);
    s->dropped_unreported = 0;
  }
}

void Runtime::dispatch(const std::function<void()>& body, const std::string& channel) {
  ++counters_.received;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    body();
  } catch (const RejectedMessage& e) {
    ++counters_.rejected;
    log().warn("{}: rejected message on {}: {}", name_, channel, e.what());
  } catch (const DroppedMessage& e) {
    ++counters_.dropped;
    log().info("{}: dropped message on {}: {}", name_, channel, e.what());
  } catch (const std::exception& e) {
    // A bug or an unforeseen input: keep running, count it, say so loudly.
    ++counters_.rejected;
    log().error("{}: handler for {} failed: {}", name_, channel, e.what());
  }
  cycle_ms_.push_back(
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
}

void Runtime::ackStep(std::int64_t utime, std::int64_t step) {
  if (step < 0) return;  // free-running: nobody waits
  step_ack_t ack{};
  ack.utime = utime;
  ack.step = step;
  ack.participant = name_;
  fillRestart(ack);
  publish(channels::kStepAck, ack);
}

bool Runtime::publishRaw(const std::string& channel, const std::vector<std::uint8_t>& bytes) {
  if (muted_) return true;
  if (lcm_->publish(channel, bytes.data(), static_cast<unsigned int>(bytes.size())) != 0)
    return false;
  ++counters_.published;
  return true;
}

void Runtime::fillRestart(step_ack_t& ack) {
  // Decided at the first live ack once the world was heard (or a journal was replayed): a test or
  // a log replay without a world never counts as a restart.
  if (!muted_ && !restart_decided_ && ack.step >= 0 &&
      (restart_ != step_ack_t::RESTART_NONE || world_heard_)) {
    restart_decided_ = true;
    if (restart_ == step_ack_t::RESTART_NONE && joinedLate()) {
      // Whatever it had learnt before is gone: say so, never silently.
      restart_ = step_ack_t::RESTART_STATE_LOST;
      restart_note_ = "joined mid-run without " + lost_state_note_;
      setDegraded("restarted at step " + std::to_string(ack.step) + ": " + restart_note_);
    }
    if (restart_ != step_ack_t::RESTART_NONE) {
      restart_step_ = ack.step;
      log().warn("{}: restarted; first step acknowledged {}: {}", name_, ack.step, restart_note_);
    }
  }
  ack.restart = restart_;
  ack.restart_step = restart_step_;
  ack.restart_note = restart_note_;
}

void Runtime::setRestarted(bool recovered, const std::string& note) {
  restart_ = recovered ? step_ack_t::RESTART_RECOVERED : step_ack_t::RESTART_STATE_LOST;
  recovered_ = recovered;
  restart_note_ = note;
  if (recovered) {
    setRunning("restarted: " + note);
  } else {
    setDegraded("restarted: " + note);
  }
}

void Runtime::dispatchRaw(const std::string& channel, const void* data, std::size_t size,
                          std::int64_t recv_utime) {
  lcm::ReceiveBuffer rbuf{};
  rbuf.data = const_cast<void*>(data);  // LCM's type; handlers only read it
  rbuf.data_size = static_cast<std::uint32_t>(size);
  rbuf.recv_utime = recv_utime;
  for (auto& s : subscriptions_)
    if (s->channel == channel) s->on_message(&rbuf);
}

void Runtime::addTimer(std::chrono::milliseconds period, std::function<void()> fn) {
  timers_.push_back({period, std::chrono::steady_clock::now() + period, std::move(fn)});
}

void Runtime::setDegraded(const std::string& detail) {
  if (state_ != daemon_status_t::STATE_DEGRADED || detail_ != detail)
    log().warn("{}: degraded: {}", name_, detail);
  state_ = daemon_status_t::STATE_DEGRADED;
  detail_ = detail;
}

void Runtime::setRunning(const std::string& detail) {
  if (state_ == daemon_status_t::STATE_DEGRADED) log().info("{}: running again", name_);
  state_ = daemon_status_t::STATE_RUNNING;
  detail_ = detail;
}

void Runtime::publishStatus() {
  reportQueueDrops();
  daemon_status_t s;
  s.utime = wallUtime();
  s.name = name_;
  s.pid = static_cast<int32_t>(::getpid());
  s.state = state_;
  s.received = counters_.received;
  s.dropped = counters_.dropped;
  s.rejected = counters_.rejected;
  s.published = counters_.published + 1;  // this status message included
  s.last_logic_utime = last_logic_utime_;
  if (cycle_ms_.empty()) {
    s.cycle_p50_ms = s.cycle_max_ms = std::numeric_limits<double>::quiet_NaN();
  } else {
    auto mid = cycle_ms_.begin() + static_cast<std::ptrdiff_t>(cycle_ms_.size() / 2);
    std::nth_element(cycle_ms_.begin(), mid, cycle_ms_.end());
    s.cycle_p50_ms = *mid;
    s.cycle_max_ms = *std::max_element(cycle_ms_.begin(), cycle_ms_.end());
    cycle_ms_.clear();
  }
  s.detail = detail_;
  s.backlog = max_backlog_;
  max_backlog_ = 0;
  publish(channels::kStatus, s);
}

void Runtime::runDueTimers() {
  if (muted_) return;
  const auto now = std::chrono::steady_clock::now();
  for (auto& t : timers_) {
    if (now >= t.next) {
      t.next = now + t.period;
      try {
        t.fn();
      } catch (const std::exception& e) {
        log().error("{}: timer failed: {}", name_, e.what());
      }
    }
  }
}

int Runtime::pollTimeoutMs(std::chrono::steady_clock::duration until_due) {
  const long ms = std::chrono::ceil<std::chrono::milliseconds>(until_due).count();
  return static_cast<int>(std::clamp<long>(ms, 0, 1000));
}

int Runtime::msUntilNextTimer() const {
  const auto now = std::chrono::steady_clock::now();
  int best = 1000;
  for (const auto& t : timers_) best = std::min(best, pollTimeoutMs(t.next - now));
  return best;
}

void Runtime::addReadable(int fd, std::function<void()> fn) {
  readables_.push_back({fd, std::move(fn)});
}

void Runtime::runReadables(const pollfd* fds) {
  for (std::size_t i = 0; i < readables_.size(); ++i) {
    if (!(fds[i].revents & (POLLIN | POLLERR | POLLHUP))) continue;
    try {
      readables_[i].fn();
    } catch (const std::exception& e) {
      log().error("{}: input handler failed: {}", name_, e.what());
    }
  }
}

int Runtime::spinFor(int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  int handled = 0;
  while (true) {
    runDueTimers();
    const auto now = std::chrono::steady_clock::now();
    int wait_ms = static_cast<int>(
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now).count());
    wait_ms = std::max(0, std::min(wait_ms, msUntilNextTimer()));
    pump(kPumpBudget);
    answerNewPeers();
    if (handleNext()) {
      ++handled;
      continue;
    }
    if (!readables_.empty()) {
      // LCM's fd and the other inputs' in one wait; LCM then reads without blocking.
      std::vector<pollfd> fds{{lcm_->getFileno(), POLLIN, 0}};
      for (const auto& r : readables_) fds.push_back({r.fd, POLLIN, 0});
      const int n = ::poll(fds.data(), fds.size(), wait_ms);
      if (n < 0 && errno != EINTR) return handled;
      if (n > 0) runReadables(fds.data() + 1);
      if (n > 0 && (fds[0].revents & POLLIN)) lcm_->handleTimeout(0);
      if (n > 0) continue;
      if (std::chrono::steady_clock::now() >= deadline) return handled;
      continue;
    }
    // handleTimeout(0) is a non-blocking poll; a negative timeout would return -1 at once.
    // A message it receives is only queued: the next round handles it.
    const int r = lcm_->handleTimeout(wait_ms);
    if (r > 0) continue;
    if (r < 0 && errno != EINTR) return handled;
    if (std::chrono::steady_clock::now() >= deadline) return handled;
  }
}

void Runtime::requestStop() {
  stop_ = true;
  const char c = 'q';
  if (stop_pipe_[1] >= 0) [[maybe_unused]]
    auto n = ::write(stop_pipe_[1], &c, 1);
}

int Runtime::run() {
  installSignalHandlers();
  if (state_ == daemon_status_t::STATE_STARTING) state_ = daemon_status_t::STATE_RUNNING;
  addTimer(std::chrono::milliseconds(1000), [this] {
    checkDuplicate();
    flushLogSuppressions();
    publishStatus();
  });
  g_starting.store(false);
  publishStatus();
  log().info("{}: ready (pid {})", name_, ::getpid());
  // LCM, the signal and stop pipes, then the other inputs (addReadable).
  std::vector<pollfd> fds{
      {lcm_->getFileno(), POLLIN, 0}, {g_signal_pipe[0], POLLIN, 0}, {stop_pipe_[0], POLLIN, 0}};
  for (const auto& r : readables_) fds.push_back({r.fd, POLLIN, 0});
  while (!stop_ && !g_signalled.load()) {
    runDueTimers();
    // Messages still waiting in the queues (a wake-up handles at most 1000): do not sleep.
    const int n = ::poll(fds.data(), fds.size(), inbox_->waiting > 0 ? 0 : msUntilNextTimer());
    if (n < 0) {
      if (errno == EINTR) continue;
      log().error("{}: poll failed: {}", name_, std::strerror(errno));
      return kExitRuntime;
    }
    if ((fds[1].revents & POLLIN) || (fds[2].revents & POLLIN)) break;
    if (n > 0) runReadables(fds.data() + 3);
    if ((fds[0].revents & POLLIN) || inbox_->waiting > 0) {
      // Move what LCM received into the bounded queues, then handle the oldest, again and again
      // (at most 1000 per wake-up, so that a burst does not starve the status timer): LCM's own
      // queue stays short whatever a handler costs. How many wait is the daemon's backlog (a
      // queue that grows when it cannot keep up). A stop is looked at between any two messages:
      // a backlog never delays it by more than the one message in hand.
      pump(kPumpBudget);
      if (inbox_->waiting > 1)
        max_backlog_ = std::max(
            max_backlog_, static_cast<int>(std::min<std::size_t>(inbox_->waiting - 1, 1U << 30U)));
      int handled = 0;
      while (handled < 1000 && !stop_ && !g_signalled.load() && handleNext()) {
        ++handled;
        pump(kPumpBudget);
      }
    }
    answerNewPeers();
  }
  if (g_signalled.load()) log().info("{}: signal received, stopping", name_);
  state_ = daemon_status_t::STATE_STOPPING;
  publishStatus();
  return kExitOk;
}

}  // namespace coopnav
