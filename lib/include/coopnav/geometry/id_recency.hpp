#pragma once
/// @file Ids in the order they were last heard of (message time), least recent first: per-id
/// state is forgotten by age or by count from the front, never by scanning every entry, so a
/// flood of new ids costs constant work per message (docs/bad-inputs.md "Caps": limits.max_ids,
/// limits.forget_after_s). Every daemon that keeps state per human id bounds it with one.

#include <cstddef>
#include <cstdint>
#include <list>
#include <optional>
#include <unordered_map>

namespace coopnav {

class IdRecency {
 public:
  struct Entry {
    std::int32_t id{0};
    std::int64_t utime{0};  ///< [us] last heard of
  };

  /// Notes `id` heard of at `utime`: it becomes the most recent. A time before the most recent
  /// one noted counts as that one (a message a little behind another), so the order from the
  /// front is also the order of time and ageing stops at the first entry young enough.
  void touch(std::int32_t id, std::int64_t utime) {
    if (!order_.empty() && utime < order_.back().utime) utime = order_.back().utime;
    const auto it = where_.find(id);
    if (it != where_.end()) {
      it->second->utime = utime;
      order_.splice(order_.end(), order_, it->second);
      return;
    }
    order_.push_back({id, utime});
    where_.emplace(id, std::prev(order_.end()));
  }

  /// Removes `id`; false if it was not there.
  bool erase(std::int32_t id) {
    const auto it = where_.find(id);
    if (it == where_.end()) return false;
    order_.erase(it->second);
    where_.erase(it);
    return true;
  }

  bool contains(std::int32_t id) const { return where_.count(id) > 0; }
  std::size_t size() const { return order_.size(); }
  bool empty() const { return order_.empty(); }

  /// The least recently heard of id; nullptr when empty.
  const Entry* oldest() const { return order_.empty() ? nullptr : &order_.front(); }

  std::optional<std::int64_t> utimeOf(std::int32_t id) const {
    const auto it = where_.find(id);
    if (it == where_.end()) return std::nullopt;
    return it->second->utime;
  }

  /// Every entry stamped `utime`, order kept: the message clock was resynchronised and the old
  /// times belong to another time base (their ages would be meaningless).
  void restamp(std::int64_t utime) {
    for (auto& e : order_) e.utime = utime;
  }

  /// How many ids forgetOld() removed, and why.
  struct Forgotten {
    std::size_t aged{0};  ///< not heard of for more than max_age_s
    std::size_t over{0};  ///< beyond max_ids (a flood of new ids)
  };

  /// Removes, least recent first, the ids not heard of for more than `max_age_s` before
  /// `now_utime`, then the least recent ones beyond `max_ids`; calls forget(id) for each before
  /// it goes (the owner drops its state for that id). Visits only what it removes plus one.
  template <class Forget>
  Forgotten forgetOld(std::int64_t now_utime, double max_age_s, std::size_t max_ids,
                      Forget&& forget) {
    Forgotten n;
    while (!order_.empty()) {
      // In double: a hostile stamp must not overflow the difference.
      const double age_s =
          (static_cast<double>(now_utime) - static_cast<double>(order_.front().utime)) * 1e-6;
      if (age_s > max_age_s) {
        ++n.aged;
      } else if (order_.size() > max_ids) {
        ++n.over;
      } else {
        break;
      }
      const std::int32_t id = order_.front().id;
      forget(id);
      erase(id);
    }
    return n;
  }

  void clear() {
    order_.clear();
    where_.clear();
  }

 private:
  std::list<Entry> order_;  ///< least recently heard of first
  std::unordered_map<std::int32_t, std::list<Entry>::iterator> where_;
};

}  // namespace coopnav
