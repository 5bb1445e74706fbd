#pragma once
/// @file The keys of "a person ahead walking the robot's way" (lib geometry/same_way.hpp), read
/// by both daemons that follow such a person: the band source (overtake.*, it follows and passes)
/// and the dialogue manager (overtake.*, it announces the pass). One declaration of each key and
/// its range; the defaults are lib's.

#include "config/config.hpp"
#include "coopnav/geometry/same_way.hpp"

namespace coopnav {

template <class V>
void visitSameWayKeys(V& v, SameWayOptions& o) {
  v("ahead_range_m", o.ahead_range_m, Range{0.5, 50.0});
  v("min_speed_along_m_s", o.min_speed_along_m_s, Range{-1.0, 1.0});
  v("standing_speed_m_s", o.standing_speed_m_s, Range{0.0, 2.0});
  v("lane_margin_m", o.lane_margin_m, Range{0.0, 5.0});
}

}  // namespace coopnav
