#pragma once
/// @file IdRecency lives in lib/ (pure, used by lib/dialogue's session too); daemons include it
/// from here as before.
#include "coopnav/geometry/id_recency.hpp"
