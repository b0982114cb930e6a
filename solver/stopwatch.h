// The stats' timings: wall-clock seconds on the steady clock, which system-time changes do not move.
#pragma once

#include <chrono>

namespace lambert {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace lambert
