// coopnav_lossy_relay: joins LCM endpoints (one udpm URL per process of a run) and forwards every
// message from each to all the others, dropping each forwarded copy with a seeded probability:
// message loss between every pair of processes, for the fault tests (scripts/faults.sh), on a
// machine without netem. Which copies are dropped depends on the seed and the messages only, not
// on their arrival order (loss_decision.hpp): the same run and seed drop the same copies. Endpoints
// given with --lossless (the logger, scripts) get every message.
//
//   coopnav_lossy_relay --endpoint URL --endpoint URL ... [--lossless URL ...]
//                       [--loss 0.1] [--seed 1]
//
// A message the relay publishes on an endpoint comes back to the relay itself (multicast
// loopback): each forwarded copy is remembered (channel + payload hash) and its echo is not
// forwarded again. Single-threaded: what one process publishes reaches each other process in
// its publishing order, as on a shared bus; only loss is added.
#include <poll.h>

#include <CLI/CLI.hpp>
#include <cstdint>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "loss_decision.hpp"
#include "stop_signals.hpp"

namespace {

std::uint64_t fnv1a(const std::string& channel, const void* data, std::size_t size) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const unsigned char* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  mix(reinterpret_cast<const unsigned char*>(channel.data()), channel.size());
  mix(static_cast<const unsigned char*>(data), size);
  return h;
}

struct Endpoint;

struct Relay {
  std::vector<std::unique_ptr<Endpoint>> endpoints;
  std::unique_ptr<coopnav::relay::LossDecider> loss;
  void forward(std::size_t from, const lcm::ReceiveBuffer* rbuf, const std::string& channel);
};

struct Endpoint {
  std::size_t index{0};
  std::string url;
  bool lossless{false};
  std::unique_ptr<lcm::LCM> lcm;
  Relay* relay{nullptr};
  std::map<std::uint64_t, int> echoes;  ///< copies we published here, not yet heard back
  std::int64_t heard{0}, forwarded_in{0}, dropped_in{0};

  static void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                        Endpoint* self) {
    if (channel.rfind("LCM_SELF_TEST", 0) == 0) return;
    const std::uint64_t h = fnv1a(channel, rbuf->data, rbuf->data_size);
    auto it = self->echoes.find(h);
    if (it != self->echoes.end()) {
      if (--it->second == 0) self->echoes.erase(it);
      return;  // our own copy coming back
    }
    ++self->heard;
    self->relay->forward(self->index, rbuf, channel);
  }
};

void Relay::forward(std::size_t from, const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  const std::uint64_t h = fnv1a(channel, rbuf->data, rbuf->data_size);
  for (auto& ep : endpoints) {
    if (ep->index == from) continue;
    if (!ep->lossless && loss->drop(from, ep->index, h)) {
      ++ep->dropped_in;
      continue;
    }
    ++ep->echoes[h];
    ep->lcm->publish(channel, rbuf->data, rbuf->data_size);
    ++ep->forwarded_in;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Forwards LCM messages between endpoints with seeded random loss (fault tests)",
               "coopnav_lossy_relay"};
  std::vector<std::string> urls, lossless;
  double loss = 0.1;
  std::uint64_t seed = 1;
  app.add_option("--endpoint", urls, "udpm URL of one process (repeat)");
  app.add_option("--lossless", lossless, "udpm URL that gets every message (logger; repeat)");
  app.add_option("--loss", loss, "probability of dropping each forwarded copy")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--seed", seed, "random seed of the drops");
  CLI11_PARSE(app, argc, argv);
  if (urls.size() + lossless.size() < 2) {
    std::cerr << "coopnav_lossy_relay: need at least two endpoints\n";
    return 2;
  }
  coopnav::tools::installStopSignals();

  Relay relay;
  relay.loss = std::make_unique<coopnav::relay::LossDecider>(seed, loss);
  auto add = [&](const std::string& url, bool is_lossless) {
    auto ep = std::make_unique<Endpoint>();
    ep->index = relay.endpoints.size();
    ep->url = url;
    ep->lossless = is_lossless;
    ep->relay = &relay;
    ep->lcm = std::make_unique<lcm::LCM>(url);
    if (!ep->lcm->good() || ep->lcm->getFileno() < 0) {
      std::cerr << "coopnav_lossy_relay: LCM endpoint " << url << " is not usable\n";
      return false;
    }
    // Unlimited queue: the relay itself must not add loss beyond the drawn one.
    lcm::Subscription* sub = ep->lcm->subscribeFunction(".*", &Endpoint::onMessage, ep.get());
    if (sub) sub->setQueueCapacity(0);
    relay.endpoints.push_back(std::move(ep));
    return true;
  };
  for (const auto& u : urls)
    if (!add(u, false)) return 1;
  for (const auto& u : lossless)
    if (!add(u, true)) return 1;

  std::vector<pollfd> fds;
  for (auto& ep : relay.endpoints) fds.push_back({ep->lcm->getFileno(), POLLIN, 0});
  std::cerr << "coopnav_lossy_relay: " << relay.endpoints.size() << " endpoints, loss " << loss
            << ", seed " << seed << std::endl;
  while (!coopnav::tools::stopRequested()) {
    const int n = ::poll(fds.data(), fds.size(), 200);
    if (n <= 0) continue;
    for (std::size_t i = 0; i < fds.size(); ++i)
      if (fds[i].revents & POLLIN) relay.endpoints[i]->lcm->handleTimeout(0);
  }
  for (const auto& ep : relay.endpoints)
    std::cerr << "coopnav_lossy_relay: " << ep->url << ": heard " << ep->heard
              << ", forwarded to it " << ep->forwarded_in << ", dropped on the way to it "
              << ep->dropped_in << "\n";
  return 0;
}
