#pragma once
/// \file
/// Wall-clock timing of the stages (steady clock). Header-only.

#include <chrono>

namespace uavip {

using SteadyClock = std::chrono::steady_clock;

/// Seconds elapsed since t0 [s].
inline double secondsSince(SteadyClock::time_point t0) {
  return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}

}  // namespace uavip
