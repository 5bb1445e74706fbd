#pragma once
/// @file Velocity command from a band (TEB: the first segment's velocity, Rösmann et al. 2013).

#include "coopnav/band/band_config.hpp"
#include "coopnav/band/timed_elastic_band.hpp"
#include "coopnav/geometry/types.hpp"

namespace coopnav {

/// Body-frame velocity (vx forward, vy left, ω) of the band's first segment, clamped to the
/// limits k (vy = 0 for a differential-drive agent). Zero for a band with < 2 poses or a
/// non-positive / non-finite first ΔT. NB: returned in a Velocity2 whose fields are read in the
/// BODY frame here.
Velocity2 bandCommand(const TimedElasticBand& band, const AgentKinematics& k);

/// World-frame velocity → body frame of heading theta_rad.
Velocity2 toBodyFrame(const Velocity2& world, double theta_rad);

}  // namespace coopnav
